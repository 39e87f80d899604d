// Stages 1 and 3 of Manocha sec. 2.2 (builder/ObjectPartition.h).
#include "builder/ObjectPartition.h"

#include <algorithm>
#include <numeric>

namespace hlod {

namespace {

double longestSide(const Aabb& box) {
  const glm::dvec3 s = box.size();
  return std::max({s.x, s.y, s.z});
}

}  // namespace

bool exceedsLimits(std::span<const PartitionItem> items, std::span<const std::uint32_t> subset,
                   const PartitionLimits& limits) {
  std::uint64_t triangles = 0;
  for (std::uint32_t i : subset) triangles += items[i].triangles;
  return triangles > limits.maxTriangles || longestSide(boxOf(items, subset)) > limits.maxExtent;
}

std::vector<std::vector<std::uint32_t>> partitionTopDown(std::span<const PartitionItem> items,
                                                         const PartitionLimits& limits) {
  std::vector<std::vector<std::uint32_t>> out;
  if (items.empty()) return out;
  std::vector<std::uint32_t> all(items.size());
  std::iota(all.begin(), all.end(), 0u);
  // An explicit stack (upper half pushed first, so the lower half comes out first): a depth
  // bounded by the data, not by the call stack.
  std::vector<std::vector<std::uint32_t>> stack;
  stack.push_back(std::move(all));
  while (!stack.empty()) {
    std::vector<std::uint32_t> group = std::move(stack.back());
    stack.pop_back();
    std::optional<Split> split;
    if (group.size() > 1 && exceedsLimits(items, group, limits)) {
      split = splitInTwo(items, group, SplitAt::CentreOfMass);
      if (split) {
        std::uint64_t triangles = 0;
        for (std::uint32_t i : group) triangles += items[i].triangles;
        // Over the extent only: a split that leaves a half as long as the group shrinks nothing.
        const double side = longestSide(boxOf(items, group));
        const bool shrinks = std::max(longestSide(boxOf(items, split->lower)),
                                      longestSide(boxOf(items, split->upper))) < side;
        if (triangles <= limits.maxTriangles && !shrinks) split.reset();
      }
    }
    if (!split) {
      std::sort(group.begin(), group.end());
      out.push_back(std::move(group));
      continue;
    }
    stack.push_back(std::move(split->upper));
    stack.push_back(std::move(split->lower));
  }
  return out;
}

}  // namespace hlod
