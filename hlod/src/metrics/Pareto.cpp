#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "hlod/metrics/ImageMetrics.h"

namespace hlod::metrics {

std::vector<std::size_t> paretoFront(std::span<const std::pair<double, double>> points) {
  std::vector<std::size_t> order;
  order.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!std::isnan(points[i].first) && !std::isnan(points[i].second)) order.push_back(i);
  }
  // By x, then y, then index: a sweep in this order meets each point after every point that
  // could dominate it, and the first of identical points first.
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (points[a].first != points[b].first) return points[a].first < points[b].first;
    if (points[a].second != points[b].second) return points[a].second < points[b].second;
    return a < b;
  });
  // A point is on the front when its y is below that of every point before it (those have a
  // smaller or equal x); an equal y means an earlier point is no worse in both.
  std::vector<std::size_t> front;
  double bestY = std::numeric_limits<double>::infinity();
  for (std::size_t i : order) {
    if (points[i].second < bestY || (front.empty() && points[i].second == bestY)) {
      front.push_back(i);
      bestY = points[i].second;
    }
  }
  return front;
}

}  // namespace hlod::metrics
