#pragma once
// Closing T-junctions at the seams between HLOD nodes (beyond Lakhia III-A, which only minimises
// cracks).
//
// Cut vertices are locked during simplification, so both sides of a cutting plane keep the same
// chain of seam edges. But a finer node is cut again by its own planes, and where such a plane Q
// crosses the seam on plane P it adds a vertex in the middle of a seam edge. The coarser node on
// the other side of P (or a node under another parent) lacks that vertex: a T-junction, which a
// rasteriser can show as a row of missing pixels. (Cuts through a point where two planes meet can
// also leave slivers whose vertices one side has and the other lacks.) The builder records every
// vertex of every piece, at every level, that lies on one of the piece's cutting planes, and then
// inserts those vertices into the seam edges of every node, bit for bit, so that both sides of
// every seam have the same vertices and edges.
#include <cstddef>
#include <map>
#include <span>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/builder/PlaneSplit.h"

namespace hlod {

class SeamVertices {
 public:
  // Records the vertices of mesh that lie on one of planes (the planes bounding it).
  void collect(const Mesh& mesh, std::span<const CutPlane> planes);
  void merge(const SeamVertices& other);
  std::size_t size() const;

  // Splits every edge of mesh that lies in one of planes at the recorded vertices strictly inside
  // it (the triangle becomes a fan from the corner opposite, or around its centre when more than
  // one edge is split). New vertices take the recorded position
  // exactly and interpolated normals and texture coordinates. Returns the number of vertices
  // inserted.
  std::size_t insertInto(Mesh& mesh, std::span<const CutPlane> planes) const;

 private:
  struct OnPlane {
    std::vector<glm::dvec3> byU, byV;  // the plane's vertices sorted on each in-plane axis
  };
  static void sortPlane(const CutPlane& plane, OnPlane& vertices);
  // Recorded vertices strictly inside segment a-b (which lies in plane), ordered from a to b,
  // with their parameter t along the segment.
  void verticesOnSegment(const CutPlane& plane, const glm::dvec3& a, const glm::dvec3& b,
                         std::vector<std::pair<double, glm::dvec3>>& out) const;

  std::map<CutPlane, OnPlane> planes_;
};

}  // namespace hlod
