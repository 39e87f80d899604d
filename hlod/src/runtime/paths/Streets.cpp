// The streets of a city model (runtime/paths/Streets.h).
#include "runtime/paths/Streets.h"

#include <algorithm>
#include <string>
#include <utility>

namespace hlod {

std::vector<double> streetsAlong(const Skeleton& sk, int axis, double minGap) {
  std::vector<std::pair<double, double>> iv;
  for (std::uint32_t r : sk.blockRoots()) {
    if (r >= sk.nodes.size() || sk.nodes[r].bounds.empty()) continue;
    iv.push_back({sk.nodes[r].bounds.min[axis], sk.nodes[r].bounds.max[axis]});
  }
  std::sort(iv.begin(), iv.end());
  std::vector<double> centres;
  double hi = iv.empty() ? 0.0 : iv.front().second;
  for (std::size_t i = 1; i < iv.size(); ++i) {
    if (iv[i].first - hi >= minGap) centres.push_back((iv[i].first + hi) * 0.5);
    hi = std::max(hi, iv[i].second);
  }
  if (!centres.empty()) return centres;
  constexpr double kTouch = 0.05;  // metres
  std::vector<double> ends;
  for (const auto& a : iv) ends.push_back(a.second);
  std::sort(ends.begin(), ends.end());
  for (const auto& a : iv) {
    const auto it = std::lower_bound(ends.begin(), ends.end(), a.first - kTouch);
    if (it == ends.end() || *it > a.first + kTouch) continue;
    if (!centres.empty() && a.first - centres.back() <= minGap) continue;
    // A line some other block crosses (e.g. the middle of a cell's courtyard) is no street.
    const bool crossed = std::any_of(iv.begin(), iv.end(), [&](const auto& b) {
      return b.first < a.first - kTouch && b.second > a.first + kTouch;
    });
    if (!crossed) centres.push_back(a.first);
  }
  return centres;
}

Status requireZUp(const char* kind, const Skeleton& sk) {
  if (sk.up == UpAxis::Z) return Ok{};
  return makeError(std::string(kind) + " path: defined for z-up cities, and this store is " +
                   upAxisName(sk.up) + "-up (use --kind orbit, or rebuild with --up z if the " +
                   "model is a city)");
}

}  // namespace hlod
