#pragma once
// Triangulation of planar polygons with holes by ear clipping (D. Eberly, "Triangulation by Ear
// Clipping", Geometric Tools 2002-2015): each ring is projected onto the polygon's best-fit plane
// (the Newell normal of the outer ring), holes are bridged into the outer ring from their
// rightmost vertex to a visible outer vertex, and ears are clipped from the one merged ring.
// Used for CityJSON surfaces (non-convex faces, windows as holes); works in double precision
// relative to the first vertex, so coordinates of a few million metres keep millimetres.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace hlod {

enum class EarClipStatus {
  Ok,          // every triangle found
  Degenerate,  // the outer ring has no area (fewer than 3 distinct points, or all collinear):
               // no triangles
  Partial,     // a self-intersecting or numerically hopeless ring: the ears found so far
};

struct EarClipResult {
  EarClipStatus status = EarClipStatus::Ok;
  // Indices into the rings' points taken in order (outer ring first, then each hole), wound as
  // the outer ring: counter-clockwise seen from the side its Newell normal points to.
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::size_t droppedHoles = 0;  // holes without area, or outside the outer ring
};

// Triangulates rings[0] (the outer ring) with holes rings[1..]. A ring may repeat its first point
// at the end; consecutive duplicates and collinear points are allowed. A simple polygon of n
// distinct points and h holes gives n - 2 + 2h triangles.
EarClipResult earClip(const std::vector<std::vector<glm::dvec3>>& rings);

// The Newell normal of a ring (not normalised: its length is twice the ring's area).
glm::dvec3 newellNormal(const std::vector<glm::dvec3>& ring);

}  // namespace hlod
