#pragma once
// Splitting a mesh by an axis-aligned cutting plane (Lakhia III-A, Fig. 4).
//
// A triangle that crosses the plane is cut at the plane: two new vertices on the crossed edges and
// three triangles (or, when one vertex lies exactly on the plane, one new vertex and two
// triangles). Nothing is dropped or duplicated, so the areas of the two halves add up to the area
// of the input. New vertices get interpolated normals and texture coordinates, and their
// coordinate along the axis is exactly the plane's value, so both halves share them bit for bit.
#include <utility>
#include <vector>

#include "hlod/Mesh.h"

namespace hlod {

// An axis-aligned cutting plane p[axis] == value.
struct CutPlane {
  int axis = 0;
  double value = 0.0;
  bool contains(const glm::dvec3& p) const { return p[axis] == value; }
  bool operator<(const CutPlane& o) const {
    return axis != o.axis ? axis < o.axis : value < o.value;
  }
  bool operator==(const CutPlane& o) const { return axis == o.axis && value == o.value; }
};

struct PlaneSplitResult {
  Mesh below;  // triangles with all vertices at or below the plane (p[axis] <= value)
  Mesh above;  // triangles with all vertices at or above the plane (and none below)
};

// axis: 0, 1 or 2. Triangles lying in the plane go below. Both halves keep the input's material
// (baseColor, texture) and carry only the vertices they use.
PlaneSplitResult splitByPlane(const Mesh& mesh, int axis, double value);

// Splits by levelFactor - 1 planes perpendicular to the longest dimension of box, at equal widths,
// into levelFactor pieces ordered along the axis. Also returns the planes' axis and positions.
struct SlabSplit {
  int axis = 0;
  std::vector<double> planes;
  std::vector<Mesh> pieces;
};
SlabSplit splitIntoSlabs(const Mesh& mesh, const Aabb& box, int levelFactor);

// Index of the longest dimension of box (0 = x on ties).
int longestAxis(const Aabb& box);

// Sum of triangle areas, in double.
double surfaceArea(const Mesh& mesh);

}  // namespace hlod
