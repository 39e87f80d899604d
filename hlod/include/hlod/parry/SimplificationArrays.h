#pragma once
// Parry et al., "Hierarchical organization of urban models", sec. 5: the simplification arrays.
// "The algorithm maintains an ordered array of combined child vertices, decimated triangles,
// triangle increments, and vertex references. Starting with the smallest splat size in the
// facade hierarchy (excluding leaf nodes), we combine child vertices into their parent and
// determine which if any polygons have been decimated." Two vertices decimate the triangles that
// have both (0 when they share no edge, 1 or 2 across an edge); the rest of their triangles now
// reference the parent. "Once we have the resultant simplification arrays, we can render the
// model with any number of triangles less than the original mesh ... Rendering only requires
// drawing the triangles from the current triangle index to the end of the array."
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/parry/SphereHierarchy.h"

namespace hlod {

struct SimplificationArrays {
  // The combined child vertices (sphere nodes), two per combination, smallest splat size first;
  // a pair's parent is their hierarchy parent.
  std::vector<std::uint32_t> vertices;
  // Every triangle of the mesh, three vertices (leaves) each: the decimated ones in the order they
  // were decimated, then those no combination decimates (the coarsest mesh: triangles between
  // silhouette vertices and groups that are never combined).
  std::vector<std::uint32_t> triangles;
  // Per combination: how many triangles it decimated.
  std::vector<std::uint32_t> increments;
  // Per vertex (leaf): the sphere it references once every combination is made.
  std::vector<std::uint32_t> references;
  // Per entry of triangles (three apart): the input triangle it is (its index in the indices).
  std::vector<std::uint32_t> triangleIds;

  std::size_t triangleCount() const { return triangles.size() / 3; }
  // Triangles left when every combination is made.
  std::size_t minTriangles() const;
};

// Runs the combinations of the hierarchy over a mesh's triangles (three leaves each; triangles
// with a repeated vertex are left out).
SimplificationArrays buildSimplificationArrays(const SphereHierarchy& hierarchy,
                                               std::span<const std::uint32_t> indices);

// The arrays as a Progression over the hierarchy's nodes (each child moves into its parent),
// whose triangles are `triangles`: what progressiveIndices draws from.
Progression progressionOf(const SphereHierarchy& hierarchy, const SimplificationArrays& arrays);

// A mesh of n triangles from the arrays, ready to store: the vertices (sphere nodes) it uses,
// numbered from 0 in `vertices`, its triangles in decimation order, and the combinations still to
// come in those numbers (a node drawn from n down to the coarsest without the arrays above it).
// The cut lies at the boundary between combinations nearest n: a combination of two clusters
// decimates every triangle between them at once, so the cut may hold a few more or fewer than n.
struct ProgressiveCut {
  std::vector<std::uint32_t> vertices;     // sphere node of each vertex of the cut
  std::vector<std::uint32_t> indices;      // its triangles, in decimation order
  std::vector<std::uint32_t> triangleIds;  // per triangle: the input triangle it is
  Progression progression;                 // the combinations left, in the cut's vertex numbers
  double splatSize = 0.0;                  // radius of the last combination made (0: none)
};
ProgressiveCut cutArrays(const SphereHierarchy& hierarchy, const SimplificationArrays& arrays,
                         std::size_t n);

}  // namespace hlod
