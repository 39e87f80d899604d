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
      std::uint64_t triangles = 0;
      for (std::uint32_t i : group) triangles += items[i].triangles;
      // Over the extent only: a split that leaves a half as long as the group shrinks nothing;
      // across the group's longest side then, or not at all (polygons spanning it all).
      const Aabb box = boxOf(items, group);
      const auto shrinks = [&](const Split& s) {
        return std::max(longestSide(boxOf(items, s.lower)), longestSide(boxOf(items, s.upper))) <
               longestSide(box);
      };
      if (split && triangles <= limits.maxTriangles && !shrinks(*split)) {
        const glm::dvec3 size = box.size();
        const int longest = size.x >= size.y && size.x >= size.z ? 0 : size.y >= size.z ? 1 : 2;
        split = splitInTwo(items, group, SplitAt::CentreOfMass, longest);
        if (split && !shrinks(*split)) split.reset();
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
