#pragma once
// Mesh simplification for the HLOD levels (Lakhia III-A used QSlim). Three implementations behind
// one interface: meshoptimizer's edge-collapse simplifier (default, "meshopt"), OpenMesh's
// quadric decimater ("openmesh"), and Parry's sphere-hierarchy vertex clustering ("parry",
// hlod/parry/ParryPiece.h), which replaces simplify() as a whole (it moves vertices to the
// averages of their clusters, and gives the mesh its simplification arrays).
//
// Both simplify the shape only: the base class welds vertices by position (so texture seams and
// the per-face corners of boxes do not pin the mesh), hands the implementation positions,
// triangles and lock flags, and gives the kept triangles back their attributes by choosing, at
// each corner, the input vertex at that position whose normal best matches the triangle (a box
// face keeps its own texture coordinates). Locked vertices (the builder's cut vertices) are never
// removed or moved, so neighbouring nodes meet exactly. Output vertices are copies of input
// vertices (positions, normals and texture coordinates bit for bit); no vertex is moved.
#include <cstddef>
#include <limits>
#include <memory>
#include <string_view>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/Result.h"

namespace hlod {

struct SimplifiedMesh {
  Mesh mesh;                    // compact: only the vertices the kept triangles use
  double geometricError = 0.0;  // estimated deviation from the input, world units
};

// The flags of Simplifier::simplify's `locked`: a vertex kept where it is, or one kept on the
// block's outline. Edge collapses may slide an outline vertex along a straight run of the open
// border it lies on (they move open-border vertices only along the border), which keeps the
// outline exactly; vertex clustering, which would move it off, keeps it in place.
inline constexpr std::uint8_t kVertexLocked = 1;
inline constexpr std::uint8_t kVertexOnOutline = 2;

class Simplifier {
 public:
  virtual ~Simplifier() = default;
  virtual const char* name() const = 0;
  // Simplifies toward targetTriangles (may stay above it when locked vertices forbid more, or
  // where reaching it would leave part of the surface farther than errorLimit, world units,
  // from the result). locked holds one flag per vertex of mesh (or is empty: nothing locked):
  // 0, kVertexLocked or kVertexOnOutline; a position takes the strongest flag of its vertices. A
  // mesh already at or below the target comes back unchanged. No kept triangle faces away from the
  // surface it stands for.
  // (parry: the mesh must be welded, as the builder's pieces are; its result always has a
  // progression, down to its faces' outlines, and no vertex of it is a copy of an input vertex
  // but the silhouette ones; errorLimit plays no part.)
  virtual SimplifiedMesh simplify(
      const Mesh& mesh, std::size_t targetTriangles, const std::vector<std::uint8_t>& locked = {},
      double errorLimit = std::numeric_limits<double>::infinity()) const;
  // simplify for a union of separate coarse meshes (a cell node's children, each open where it
  // meets the others and its ground): edge collapses stall on those borders in every round of
  // the shape guard, so vertex clustering finishes each round, not only the first. (parry:
  // simplify, whose clustering needs no help.)
  virtual SimplifiedMesh simplifyUnion(const Mesh& mesh, std::size_t targetTriangles,
                                       const std::vector<std::uint8_t>& locked,
                                       double errorLimit) const;

  // What the implementations see: one vertex per distinct position.
  struct Shape {
    std::vector<glm::dvec3> positions;
    std::vector<std::uint32_t> indices;  // no repeated vertex in a triangle
    std::vector<std::uint8_t> locked;  // one flag per position (0, kVertexLocked, kVertexOnOutline)
  };
  struct ReducedShape {
    std::vector<std::uint32_t> indices;  // kept triangles, indices into Shape::positions
    double geometricError = 0.0;         // world units
  };

 private:
  SimplifiedMesh simplifyShape(const Mesh& mesh, std::size_t targetTriangles,
                               const std::vector<std::uint8_t>& locked, double errorLimit,
                               bool clusterEveryRound) const;

 protected:
  // The simplifier proper, for a non-empty shape above the target; it may stop above the target
  // where going on would pass errorLimit (world units).
  virtual ReducedShape reduce(const Shape& shape, std::size_t targetTriangles,
                              double errorLimit) const = 0;
};

// "meshopt", "openmesh" or "parry"; an Error naming the choices otherwise.
Result<std::unique_ptr<Simplifier>> makeSimplifier(std::string_view name);

// Merges vertices whose position and texture coordinate are equal (normals of merged vertices
// are averaged), and drops triangles with an invalid index or a repeated vertex. Vertices with
// equal positions but different texture coordinates stay apart (a texture seam).
Mesh weldVertices(const Mesh& mesh);

// Moves vertices to the order the triangles use them and drops unused ones.
Mesh compactVertices(const Mesh& mesh);

}  // namespace hlod
