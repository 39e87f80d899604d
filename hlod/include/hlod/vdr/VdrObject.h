#pragma once
// One object of view-dependent rendering (Manocha sec. 3): a mesh's vertex hierarchy, its
// cluster hierarchy (sec. 3.1), and what is drawn at a face's corners, in the form the node
// store keeps (hlod/store/VdrStore.h) and the runtime refines (VdrRuntime).
//
// Drawing attributes: the hierarchy is of the shape (positions welded), but a face's corner is
// drawn with a wedge, a vertex of the input welded by position and texture coordinate, with its
// normal and texture coordinate (Hoppe 1996's wedges). Every vertex of the hierarchy stands at a
// leaf's position, so a corner moved to vertex x is drawn with one of the wedges at x's leaf: the
// one of the face's own chart (the connected set of input faces that share wedges: one texture
// island), else the one whose normal is nearest the corner's own input normal (a box's corner
// keeps each face's normal).
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "hlod/vdr/ClusterHierarchy.h"
#include "hlod/vdr/VertexHierarchy.h"

namespace hlod::vdr {

struct VdrObject {
  glm::dvec3 centre{0.0};  // what stored positions and drawn vertices are relative to
  VertexHierarchy hierarchy;
  ClusterHierarchy clusters;
  // Wedges, sorted by leaf: the wedges at leaf l are [leafWedgeStart[l], leafWedgeStart[l + 1]).
  std::vector<std::uint32_t> wedgeLeaf;
  std::vector<glm::vec3> wedgeNormal;
  std::vector<glm::vec2> wedgeTexCoord;  // empty: the mesh has no texture coordinates
  std::vector<std::uint32_t> wedgeChart;
  std::vector<std::uint32_t> leafWedgeStart;             // leaves + 1
  std::vector<std::array<std::uint32_t, 3>> faceWedges;  // per face of the hierarchy
  glm::vec4 baseColor{0.8f, 0.8f, 0.8f, 1.0f};
  bool oneSided = false;
  std::shared_ptr<const Image> texture;

  // The wedge to draw face t's corner i with when that corner stands at vertex `at`.
  std::uint32_t cornerWedge(std::uint32_t t, int i, std::uint32_t at) const;
  Aabb bounds() const;  // of the leaves
  // Bytes the decoded object holds (for memory caps and reports).
  std::uint64_t memoryBytes() const;
};

struct VdrBuildOptions {
  HierarchyOptions hierarchy;
  ClusterOptions clusters;
  // Virtual edges within this fraction of the mesh's bounding diagonal (when
  // hierarchy.virtualEdgeDistance is 0): disjoint parts closer than that may merge.
  double virtualEdgeFraction = 0.01;
  // The clusters' error floor (when clusters.errorFloor is 0) as this fraction of the mesh's
  // bounding diagonal: the error ratio counts smaller errors as this. Flat facades collapse at
  // errors of 1e-9 m and less; floored at the smallest of them, a cluster could not hold such a
  // vertex beside one of a millimetre, and a city block made 8,000 clusters of 4 vertices.
  double errorFloorFraction = 1e-4;
};

// Builds the object of a mesh (welded by position and texture coordinate, as the builder's
// blocks are; its normals, or computed ones). locked: one flag per vertex (or empty), as
// hierarchyInputOf. An Error for what buildVertexHierarchy refuses, or a mesh without faces.
Result<VdrObject> buildVdrObject(const Mesh& mesh, const std::vector<std::uint8_t>& locked = {},
                                 const VdrBuildOptions& options = {});

}  // namespace hlod::vdr
