#pragma once
// Dividing a piece of a block among its children (Lakhia III-A, Fig. 4), without cutting it.
//
// The paper cuts the piece at levelFactor - 1 planes perpendicular to its longest dimension. Here
// the planes only choose where each triangle goes: a triangle belongs, whole, to the slab its
// centroid lies in. So the leaves hold exactly the input triangles (plane cuts had made 1.25-2.1x
// as many), and the border between two pieces is a chain of input edges that both sides have: with
// the border's vertices locked while simplifying, every two nodes that meet share it vertex for
// vertex, at any two levels, and no seam needs repairing. A child's box may reach past its slab by
// part of a triangle.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "hlod/Mesh.h"

namespace hlod {

struct SlabPartition {
  int axis = 0;
  std::vector<double> planes;                         // levelFactor - 1, ascending
  std::vector<std::vector<std::uint32_t>> triangles;  // per slab: triangle indices of the mesh
};

// Slabs of equal width along the longest dimension of the triangles' centroids (for a piece of
// many triangles, about its own longest dimension). A centroid on a plane goes to the slab below
// it, so the first and the last slab are empty only when all centroids lie on one plane.
SlabPartition partitionIntoSlabs(const Mesh& mesh, int levelFactor);

// Merges each slab of fewer than minTriangles triangles (empty ones included) into the smaller of
// its neighbours, dropping the plane between them, until every slab has minTriangles or one slab
// is left: equal widths over a piece whose triangles bunch up leave slabs of a few triangles
// (a single street triangle), which would become crumbs of nodes.
void mergeSmallSlabs(SlabPartition& partition, std::size_t minTriangles);

// Slabs along the same axis holding about equal numbers of triangles (planes at the centroids'
// quantiles; ties on a plane go below, and an emptied slab is dropped): for a piece whose
// equal-width slabs all but one fall below a node's size, such as a block whose few street
// triangles reach far beyond its buildings.
SlabPartition partitionByCount(const Mesh& mesh, int levelFactor);

// The children of a piece of a block (buildBlockHierarchy): levelFactor slabs of equal width
// (partitionIntoSlabs), the small ones merged (mergeSmallSlabs with minLeafTri), or by count
// (partitionByCount) when that leaves one. One slab: the centroids all lie on one plane.
SlabPartition divideIntoSlabs(const Mesh& piece, int levelFactor, std::size_t minLeafTri);

// Halves the triangles (indices into centroids) at the middle of their centroids' longest extent
// until each part has at most maxTriangles (cutIntoBlocks). Both halves of a cut are non-empty,
// so parts only shrink; triangles whose centroids coincide cannot be separated and stay one part.
// The depth bound keeps the recursion's stack small for any spread of centroids (call with 0).
void halveUntilSmall(const std::vector<glm::dvec3>& centroids, std::vector<std::uint32_t> triangles,
                     std::size_t maxTriangles, int depth,
                     std::vector<std::vector<std::uint32_t>>& out);

// The centroid of triangle t.
glm::dvec3 centroid(const Mesh& mesh, std::size_t t);

// The triangles of mesh listed in `triangles`, with only the vertices they use, in the order they
// use them, and the mesh's material. origin (when given) receives, per vertex, its index in mesh.
Mesh subMesh(const Mesh& mesh, std::span<const std::uint32_t> triangles,
             std::vector<std::uint32_t>* origin = nullptr);

// Index of the longest dimension of box (0 = x on ties).
int longestAxis(const Aabb& box);

}  // namespace hlod
