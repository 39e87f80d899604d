// Which node the loader reads next (runtime/loader/LoadSchedule.h).
#include "runtime/loader/LoadSchedule.h"

#include <algorithm>
#include <cmath>

namespace hlod {

void LoadSchedule::set(std::unordered_map<std::uint32_t, double>& set,
                       std::span<const LoadRequest> requests, std::size_t nodeCount) {
  set.clear();
  for (const LoadRequest& r : requests) {
    if (r.node >= nodeCount || !std::isfinite(r.priority)) continue;
    auto [it, inserted] = set.try_emplace(r.node, r.priority);
    if (!inserted) it->second = std::max(it->second, r.priority);
  }
}

void LoadSchedule::setWanted(std::span<const LoadRequest> requests, std::size_t nodeCount) {
  set(wanted_, requests, nodeCount);
  dirty_ = true;
}

void LoadSchedule::setPrefetch(std::span<const LoadRequest> requests, std::size_t nodeCount) {
  set(prefetch_, requests, nodeCount);
  dirty_ = true;
}

double LoadSchedule::priorityOf(std::uint32_t node) const {
  double p = -1.0;
  if (auto it = wanted_.find(node); it != wanted_.end()) p = std::max(p, it->second);
  if (auto it = prefetch_.find(node); it != prefetch_.end()) p = std::max(p, it->second);
  return p;
}

std::uint32_t LoadSchedule::choose(
    const Skeleton& skeleton, std::uint32_t lastFinished, double siblingRatio,
    const NodeTest& pending, const NodeTest& loadable,
    const std::function<bool(std::uint32_t node, double priority)>& fits,
    const NodeTest& neverFits) {
  if (dirty_) {
    order_.clear();
    auto add = [&](const std::unordered_map<std::uint32_t, double>& m) {
      for (const auto& [n, p] : m) {
        if (pending(n)) order_.push_back({priorityOf(n), n});
      }
    };
    add(wanted_);
    add(prefetch_);
    std::sort(order_.begin(), order_.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    order_.erase(std::unique(order_.begin(), order_.end()), order_.end());
    dirty_ = false;
  }
  // A node that does not fit even after evicting everything less important rarely has a
  // lower-priority successor that does (it may evict less): try a few, not the whole list,
  // since each try scans the resident set.
  int roomTries = 4;
  // The next sibling of the node loaded last, stored right after it: it continues the read, and
  // its group switches only once all of it is resident.
  const std::uint32_t next = lastFinished == kNoNode ? kNoNode : lastFinished + 1;
  const auto& nodes = skeleton.nodes;
  if (next < nodes.size() && nodes[next].parent != kNoNode &&
      nodes[next].parent == nodes[lastFinished].parent && loadable(next)) {
    const double p = priorityOf(next);
    const double best = order_.empty() ? 0.0 : order_.front().first;
    if (p >= 0.0 && p >= siblingRatio * best && fits(next, p)) return next;
  }
  // The order may go out of date while fits() makes room (an eviction marks it): it is walked as
  // it was built.
  for (auto it = order_.begin(); it != order_.end(); ++it) {
    // A node that can never fit costs no try: four of them at the top of the list would
    // otherwise stop every node behind them, however small, for as long as they are wanted.
    if (!loadable(it->second) || neverFits(it->second)) continue;
    if (fits(it->second, it->first)) return it->second;
    if (--roomTries == 0) break;
  }
  return kNoNode;
}

}  // namespace hlod
