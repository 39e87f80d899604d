#pragma once
// The split of a set of objects (or polygons) in two, top down, along the axis a heuristic picks
// (Manocha sec. 2.2: "standard top-down techniques that group polygons based on an object's
// center or center-of-mass, along with several heuristics for selecting the split axis"). Shared
// by the partitioning stages (ObjectPartition.h) and the AABB hierarchy (AabbHierarchy.h).
// Private to the builder.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "hlod/Mesh.h"

namespace hlod {

// One thing to partition: a polygon (its centroid, box, area) or an object (its centre of mass,
// box, surface area and triangle count).
struct PartitionItem {
  glm::dvec3 centre{0.0};
  Aabb box;
  double mass = 1.0;            // weight of its centre: the area it stands for (> 0)
  std::uint64_t triangles = 1;  // how much it weighs in a node
};

enum class SplitAt {
  CentreOfMass,  // the plane through the items' centre of mass (the partitioning stages)
  Median,        // the plane that halves their triangles (the AABB hierarchy: balance)
};

struct Split {
  int axis = 0;
  std::vector<std::uint32_t> lower, upper;  // item indices, both non-empty
};

// Splits `subset` (indices into items) in two by a plane perpendicular to an axis, an item going
// to the side its centre lies on: CentreOfMass puts a centre on the plane below; Median sorts the
// items along the axis and cuts where the lower part first holds half the triangles (ties in
// index order), one item at least on each side. The heuristics for the axis,
// over the axes along which the centres spread: the halves' boxes overlapping least (criterion 3
// of sec. 2.1.1), then the smaller sum of their boxes' surface areas (tight boxes), then the
// longest extent of the centres (scores within rounding of each other are equal). only >= 0:
// that axis alone. Nothing when every centre is the same point (along `only`), or subset has
// fewer than two items.
std::optional<Split> splitInTwo(std::span<const PartitionItem> items,
                                std::span<const std::uint32_t> subset, SplitAt at, int only = -1);

// The box of the items of subset.
Aabb boxOf(std::span<const PartitionItem> items, std::span<const std::uint32_t> subset);

}  // namespace hlod
