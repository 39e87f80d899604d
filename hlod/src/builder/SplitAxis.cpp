// The split-axis heuristic of the top-down stages (builder/SplitAxis.h; Manocha sec. 2.2).
#include "builder/SplitAxis.h"

#include <algorithm>
#include <cassert>
#include <cmath>
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
                                std::span<const std::uint32_t> subset, SplitAt at, int only) {
  if (subset.size() < 2) return std::nullopt;
  Aabb centres;
  for (std::uint32_t i : subset) {
    assert(i < items.size() && items[i].mass > 0.0);
    centres.extend(items[i].centre);
  }
  const glm::dvec3 spread = centres.size();
  std::optional<Split> best;
  double bestOverlap = 0.0, bestArea = 0.0, bestSpread = 0.0;
  // Equal within rounding: the halves of a flat grid have the same areas along either axis, and
  // the tie must go to the longer spread, not to the last bit.
  const auto less = [](double a, double b) {
    return a < b - 1e-9 * std::max(std::abs(a), std::abs(b));
  };
  for (int axis = 0; axis < 3; ++axis) {
    if (!(spread[axis] > 0.0) || (only >= 0 && axis != only)) continue;
    std::optional<Split> s = splitAlong(items, subset, axis, at);
    if (!s) continue;
    const Aabb lo = boxOf(items, s->lower), hi = boxOf(items, s->upper);
    const double overlap = overlapVolume(lo, hi), area = surfaceArea(lo) + surfaceArea(hi);
    const bool better =
        !best || less(overlap, bestOverlap) ||
        (!less(bestOverlap, overlap) &&
         (less(area, bestArea) || (!less(bestArea, area) && spread[axis] > bestSpread)));
    if (better) {
      best = std::move(s);
      bestOverlap = overlap;
      bestArea = area;
      bestSpread = spread[axis];
    }
  }
  return best;
}

}  // namespace hlod
