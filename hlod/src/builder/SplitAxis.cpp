// The split-axis heuristic of the top-down stages (builder/SplitAxis.h; Manocha sec. 2.2).
#include "builder/SplitAxis.h"

#include <algorithm>
#include <cassert>
#include <numeric>
#include <tuple>

#include "hlod/builder/HierarchyCriteria.h"

namespace hlod {

namespace {

double surfaceArea(const Aabb& b) {
  const glm::dvec3 s = b.size();
  return 2.0 * (s.x * s.y + s.y * s.z + s.z * s.x);
}

// The halves of subset along axis, or nothing when one would be empty.
std::optional<Split> splitAlong(std::span<const PartitionItem> items,
                                std::span<const std::uint32_t> subset, int axis, SplitAt at) {
  Split s;
  s.axis = axis;
  if (at == SplitAt::CentreOfMass) {
    double sum = 0.0, mass = 0.0;
    for (std::uint32_t i : subset) {
      sum += items[i].mass * items[i].centre[axis];
      mass += items[i].mass;
    }
    const double plane = sum / mass;
    for (std::uint32_t i : subset)
      (items[i].centre[axis] <= plane ? s.lower : s.upper).push_back(i);
  } else {
    std::vector<std::uint32_t> sorted(subset.begin(), subset.end());
    std::sort(sorted.begin(), sorted.end(), [&](std::uint32_t a, std::uint32_t b) {
      return std::tie(items[a].centre[axis], a) < std::tie(items[b].centre[axis], b);
    });
    std::uint64_t total = 0;
    for (std::uint32_t i : sorted) total += items[i].triangles;
    // The first cut where the lower part holds half the triangles, one item at least each side.
    std::size_t cut = 1;
    std::uint64_t below = items[sorted[0]].triangles;
    while (cut + 1 < sorted.size() && 2 * below < total) below += items[sorted[cut++]].triangles;
    s.lower.assign(sorted.begin(), sorted.begin() + std::ptrdiff_t(cut));
    s.upper.assign(sorted.begin() + std::ptrdiff_t(cut), sorted.end());
  }
  if (s.lower.empty() || s.upper.empty()) return std::nullopt;
  return s;
}

}  // namespace

Aabb boxOf(std::span<const PartitionItem> items, std::span<const std::uint32_t> subset) {
  Aabb box;
  for (std::uint32_t i : subset) box.extend(items[i].box);
  return box;
}

std::optional<Split> splitInTwo(std::span<const PartitionItem> items,
                                std::span<const std::uint32_t> subset, SplitAt at) {
  if (subset.size() < 2) return std::nullopt;
  Aabb centres;
  for (std::uint32_t i : subset) {
    assert(i < items.size() && items[i].mass > 0.0);
    centres.extend(items[i].centre);
  }
  const glm::dvec3 spread = centres.size();
  std::optional<Split> best;
  std::tuple<double, double, double> bestScore{};
  for (int axis = 0; axis < 3; ++axis) {
    if (!(spread[axis] > 0.0)) continue;
    std::optional<Split> s = splitAlong(items, subset, axis, at);
    if (!s) continue;
    const Aabb lo = boxOf(items, s->lower), hi = boxOf(items, s->upper);
    const std::tuple<double, double, double> score{
        overlapVolume(lo, hi), surfaceArea(lo) + surfaceArea(hi), -spread[axis]};
    if (!best || score < bestScore) {
      best = std::move(s);
      bestScore = score;
    }
  }
  return best;
}

}  // namespace hlod
