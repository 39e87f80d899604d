#pragma once
// The catwalk walk of a CAD scene (Manocha's walkthroughs of the power plant): at eye height
// along the scene's catwalks, found in its full-detail geometry; makeCatwalkPath(store) in
// CameraPath.h is this with the store's leaves and the default options.
//
// The walk: the model's horizontal extent is gridded (CatwalkOptions::cell). A floor is where a
// triangle facing up (within about 18 degrees) covers a cell's centre at least minElevation above
// the model's bottom; it is free when no triangle of the model reaches into the headroom above it
// over that cell, and walkable when a disc of `clearance` around it is free floor within a step
// (0.3 m) of its height: away from railings, posts, pipes, walls and edges. Walkable floors a
// step apart in neighbouring cells are joined; the largest network is the catwalks. The walk
// follows the longest of its shortest paths (found by two breadth-first sweeps) from one end, for
// `duration` seconds at `speed`, straightened where the straight line stays walkable; keyframes
// where it turns, at eyeHeight above the floor, looking ahead. The interpolated path is checked
// against the grid, and keyframes are added where it leaves the walkable floor, so no frame is
// ever inside a pipe, a wall or a railing.
#include <functional>

#include "hlod/Result.h"
#include "hlod/UpAxis.h"
#include "hlod/runtime/CameraPath.h"
#include "hlod/store/NodeSource.h"

namespace hlod {

struct CatwalkOptions {
  double cell = 0.25;  // grid cell, world units (metres)
  double eyeHeight = 1.7;
  double headroom = 2.1;      // free height above a floor
  double clearance = 0.5;     // free radius around the walker
  double minElevation = 2.0;  // above the model's bottom: catwalks, not the ground
  double speed = 1.4;         // metres per second
  double duration = 40.0;     // seconds, at most (less when the catwalks are shorter)
};

// Calls visit(a, b, c) for every triangle of a surface, in world coordinates; an Error stops it.
using TriangleVisitor =
    std::function<void(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)>;
using TriangleSource = std::function<Status(const TriangleVisitor&)>;

// The walk over the triangles the source gives (twice: one pass for floors, one for what stands
// above them) within bounds. An Error when no floor is walkable.
Result<CameraPath> makeCatwalkPath(const TriangleSource& triangles, const Aabb& bounds, UpAxis up,
                                   const CatwalkOptions& options = {});

// The triangles of a store's leaves (its full detail), decoded one node at a time.
TriangleSource leafTriangles(const NodeSource& source);

}  // namespace hlod
