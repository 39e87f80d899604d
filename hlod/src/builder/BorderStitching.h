#pragma once
// Welding a cell's children along the sides where they meet (builder/CellNodes.h): their
// positions put back exactly on the shared planes and seam points (snapOnto), then the
// T-junctions between the two sides split (stitchBorders), so that the children become one
// surface there and the simplification cannot open a street into a gap. Private to the builder.
#include <span>

#include "hlod/builder/HlodBuilder.h"

namespace hlod {

// Relative to a cell's diagonal, the tolerance of snapOnto and stitchBorders: far above a float's
// rounding of a vertex around its node's centre (2^-24 of the node's size), far below any detail.
constexpr double kSnap = 1e-6;

// Moves positions within `tolerance` of a plane onto it, and of a point onto the point.
void snapOnto(Mesh& mesh, std::span<const CutPlane> planes, std::span<const glm::dvec3> points,
              double tolerance);

// Splits each open-border edge lying on one of the planes at the border positions of the other
// children strictly inside it: two blocks' grounds meet at a street's middle with the same
// corners, but each dropped other straight-run vertices (kVertexOnOutline), and the T-junctions
// left would keep the street an open border, which the simplification then opens into a gap.
// Within `tolerance` of the segment, and the planes' sides run along the axis across `up`.
void stitchBorders(Mesh& mesh, std::span<const CutPlane> planes, UpAxis up, double tolerance);

}  // namespace hlod
