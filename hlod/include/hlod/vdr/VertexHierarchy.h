#pragma once
// The vertex hierarchy of view-dependent rendering (Manocha, "Interactive Display of Complex
// Environments", sec. 3; Hoppe, "View-dependent refinement of progressive meshes", SIGGRAPH 1997;
// Yoon, Salomon, Manocha, "Interactive view-dependent rendering with conservative occlusion
// culling in complex environments", IEEE Visualization 2003), built from edge collapses:
//  - "We use the edge collapse operator as the basis for our vertex hierarchies and allow virtual
//    edges so that disjoint parts of the model can be merged": the candidates are the mesh's
//    edges and virtual edges between vertices of different connected parts closer than
//    HierarchyOptions::virtualEdgeDistance (Garland and Heckbert's virtual pairs, GAPS).
//  - "The result of the operation is a new vertex that is the parent of the vertices to which
//    the operator was applied": a collapse of (kept, removed) makes a new vertex whose children
//    they are. It stands where `kept` stands (a half-edge collapse, subset placement): every
//    vertex of the hierarchy is at a position of the input, so the input's texture coordinates
//    and normals there stay valid at every level.
//  - "We store an error value corresponding to the local Hausdorff distance from the original
//    mesh with each vertex": HierarchyVertex error, see buildVertexHierarchy.
//  - "The face neighborhood is stored for each edge collapse and vertex split operation": the
//    faces around the two children just before their collapse, with their vertices then
//    (neighbourhood()); the faces around the parent just after it follow from them (the two
//    children renamed to the parent, the faces holding both gone). ActiveMesh applies an
//    operation only where the current neighbourhood is the stored one.
// Faces are the input's triangles: in any state of the hierarchy a face is drawn with each
// corner at the active ancestor of its input vertex, and is live while those three differ.
// Collapses are taken in the order of their quadric error (Garland and Heckbert 1997), and one
// that would turn a face against its own input triangle or its current side is not made.
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"
#include "hlod/Result.h"

namespace hlod::vdr {

constexpr std::uint32_t kNone = 0xffffffffu;

// One face of a stored neighbourhood: the input triangle and the vertices its corners were at.
struct StoredFace {
  std::uint32_t face = 0;
  std::array<std::uint32_t, 3> corners{};
  bool operator==(const StoredFace&) const = default;
};

// Vertices 0 .. leafCount-1 are the leaves (the input's distinct positions); the vertices made
// by collapses follow in the order they were made, so a parent's index is above its children's.
struct VertexHierarchy {
  std::uint32_t leafCount = 0;
  std::vector<glm::dvec3> leafPosition;             // per leaf
  std::vector<std::array<std::uint32_t, 3>> faces;  // the input's triangles, on leaves
  std::vector<std::uint32_t> parent;                // per vertex; kNone for a root
  // Per vertex made by a collapse (index v - leafCount): {kept, removed}.
  std::vector<std::array<std::uint32_t, 2>> children;
  std::vector<std::uint32_t> leafOf;  // per vertex: the leaf whose position it takes
  // Per vertex: the local Hausdorff distance to the input (world units), never below its
  // children's; 0 at the leaves.
  std::vector<float> error;
  // Per vertex: the radius of a sphere around it that holds its faces when it was made and its
  // children's spheres, so that an error projected over the sphere's nearest point never grows
  // from parent to child (Hoppe 1997's bounding spheres).
  std::vector<float> radius;
  // Per vertex made by a collapse: its stored neighbourhood, a range of storedFaces.
  std::vector<std::uint32_t> neighbourhoodStart;  // interior vertices + 1
  std::vector<StoredFace> storedFaces;

  std::uint32_t vertexCount() const { return std::uint32_t(parent.size()); }
  bool isLeaf(std::uint32_t v) const { return v < leafCount; }
  glm::dvec3 position(std::uint32_t v) const { return leafPosition[leafOf[v]]; }
  std::uint32_t kept(std::uint32_t v) const { return children[v - leafCount][0]; }
  std::uint32_t removed(std::uint32_t v) const { return children[v - leafCount][1]; }
  // The faces around kept(v) and removed(v) just before they were collapsed into v.
  std::span<const StoredFace> neighbourhood(std::uint32_t v) const {
    const std::uint32_t k = v - leafCount;
    return {storedFaces.data() + neighbourhoodStart[k],
            storedFaces.data() + neighbourhoodStart[k + 1]};
  }
  std::vector<std::uint32_t> roots() const;
  // The leaves numbered depth first (kept child first): per vertex, the first and last number
  // of its leaves, so that v lies below a when first[a] <= first[v] and last[v] <= last[a].
  void leafRanges(std::vector<std::uint32_t>& first, std::vector<std::uint32_t>& last) const;
};

// The input: distinct positions, triangles on them (three distinct corners each), and per
// position whether it is locked: never removed (it may still be kept), so that what the input
// shares with its neighbours (a block's seam, a city block's outline on its sides) stays put.
struct HierarchyInput {
  std::vector<glm::dvec3> positions;
  std::vector<std::array<std::uint32_t, 3>> faces;
  std::vector<std::uint8_t> locked;  // empty: nothing locked
};

// A mesh as HierarchyInput: its vertices welded by position (texture seams and the per-face
// corners of boxes join: the hierarchy is of the shape), its triangles on them less those that
// lose a corner so; locked (one flag per mesh vertex, or empty) locks a position when any of its
// vertices is. positionOf, when given, receives each mesh vertex's position index, and
// faceVertices each kept face's mesh vertices (in the order of HierarchyInput::faces).
HierarchyInput hierarchyInputOf(const Mesh& mesh, const std::vector<std::uint8_t>& locked = {},
                                std::vector<std::uint32_t>* positionOf = nullptr,
                                std::vector<std::array<std::uint32_t, 3>>* faceVertices = nullptr);

struct HierarchyOptions {
  // Vertices of different connected parts closer than this (world units) get a virtual edge
  // (the four nearest of each vertex at most). 0: no virtual edges.
  double virtualEdgeDistance = 0.0;
  std::uint32_t virtualEdgesPerVertex = 4;
  // A collapse is refused when a face it moves would face its own input triangle at less than
  // this cosine (a fold-over against the original surface), or turn against its current side.
  double minFacing = 0.05;
  // The local Hausdorff distance measures at most this many of a vertex's leaves (evenly spread
  // over them; the children's errors still bound it from below).
  std::uint32_t maxErrorSamples = 512;
};

// Collapses in quadric-error order until no collapse is left that is allowed (locks, fold-overs,
// nothing left to pair). The error of a vertex v made by a collapse is the larger of its
// children's and of the local Hausdorff distance between the input and the faces around v just
// after the collapse, both ways: from each leaf below v (the input's points it stands for) to
// those faces, and from points of those faces near v (at a third of each edge from v, and at
// the centroid of v's third of the face) to the input's triangles. An Error for an input with
// an index out of range, a face with a repeated corner, or a non-finite position.
Result<VertexHierarchy> buildVertexHierarchy(const HierarchyInput& input,
                                             const HierarchyOptions& options = {});

// The same with the collapses given (kept, removed: vertex indices as they will be numbered:
// leaves, then the vertices the earlier collapses made), in that order: no quadric order and
// no fold-over test, for hand-built hierarchies. An Error when a collapse names a vertex that
// is not active (not made yet, or already collapsed) or the same vertex twice.
struct Collapse {
  std::uint32_t kept = 0;
  std::uint32_t removed = 0;
};
Result<VertexHierarchy> buildVertexHierarchy(const HierarchyInput& input,
                                             std::span<const Collapse> collapses);

}  // namespace hlod::vdr
