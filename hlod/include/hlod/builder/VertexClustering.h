#pragma once
// Vertex clustering (Rossignac and Borrel, "Multi-resolution 3D approximations for rendering
// complex scenes", 1993), the simplifiers' fallback where edge collapses stall: every unlocked
// vertex moves to the representative of its cell in a uniform grid, and the triangles that keep
// three distinct cells remain. Locked vertices (cut vertices) stay where they are.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "hlod/builder/Simplifier.h"

namespace hlod {

// The finest grid whose result has at most targetTriangles triangles (found by bisection on the
// grid size), applied to `indices` (triangles on shape's positions). The result's triangles use
// shape's vertices; geometricError is the farthest a vertex moved.
Simplifier::ReducedShape clusterVertices(const Simplifier::Shape& shape,
                                         const std::vector<std::uint32_t>& indices,
                                         std::size_t targetTriangles);

}  // namespace hlod
