#pragma once
// Partitioning, stages 1 and 3 of Manocha sec. 2.2: "Partition large objects into sub-objects in
// the initial database (top-down)" and "Partition again to eliminate any uneven spatial clusters
// (top-down)". The same top-down split serves both: stage 1 splits an object's polygons (items:
// its triangles), stage 3 a cluster's objects (items: the objects). Private to the builder.
#include <cstdint>
#include <span>
#include <vector>

#include "builder/SplitAxis.h"

namespace hlod {

// What an object of the redefined set may be: at most maxTriangles triangles and at most
// maxExtent along any axis of its box (Manocha's "uniformly-sized objects").
struct PartitionLimits {
  std::uint64_t maxTriangles = 6000;
  double maxExtent = 0.0;  // world units; infinity: no bound
};

// True when the items of subset together exceed a limit.
bool exceedsLimits(std::span<const PartitionItem> items, std::span<const std::uint32_t> subset,
                   const PartitionLimits& limits);

// Splits the items top down (splitInTwo at the centre of mass, SplitAt::CentreOfMass) until each
// group is within the limits, holds one item, or cannot be split: every centre the same point,
// or a group over the extent only whose halves would be as large as it, along the heuristic's
// axis and across its longest side both (polygons spanning it all, as the two triangles of a
// floor slab do). Groups in depth-first order, lower half first; the
// item indices of each ascending. No item is dropped or repeated.
std::vector<std::vector<std::uint32_t>> partitionTopDown(std::span<const PartitionItem> items,
                                                         const PartitionLimits& limits);

}  // namespace hlod
