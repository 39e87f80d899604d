#pragma once
// Which node the loader reads next (Lakhia III-D: the highest-priority non-resident node): the
// priorities of this frame's wanted nodes and of the look-ahead's prefetched ones (a node's
// priority is the larger), the loadable ones in order, best first, and the choice among them.
// Private to the loader (runtime/Loader.cpp); not locked: the Loader calls it under its mutex.
#include <cstdint>
#include <functional>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "hlod/runtime/Selector.h"
#include "hlod/store/Skeleton.h"

namespace hlod {

class LoadSchedule {
 public:
  using NodeTest = std::function<bool(std::uint32_t node)>;

  // Replace this frame's wanted set, or the look-ahead's prefetch set: per node the largest of
  // its priorities; a request for a node not below nodeCount or of a priority not finite is
  // dropped. Both mark the order out of date.
  void setWanted(std::span<const LoadRequest> requests, std::size_t nodeCount);
  void setPrefetch(std::span<const LoadRequest> requests, std::size_t nodeCount);
  // The larger of the node's wanted and prefetch priorities; -1 when it is neither.
  double priorityOf(std::uint32_t node) const;

  // The order is out of date once the wanted set or the resident set changes; it is rebuilt on
  // the next choose().
  void markDirty() { dirty_ = true; }
  bool dirty() const { return dirty_; }
  // The wanted and prefetched nodes still to load, by priority, best first (ties: lower index),
  // as the last choose() built it.
  const std::vector<std::pair<double, std::uint32_t>>& order() const { return order_; }

  // The node to load next, kNoNode when none: first rebuilds the order when it is out of date,
  // from the nodes `pending` accepts (not resident, not failed). Then the next sibling of
  // `lastFinished` (stored right after it: it continues the read, and its group switches only
  // once all of it is resident) when it is loadable, fits, and is at least `siblingRatio` times
  // as important as the best node; else the best loadable node that fits. Nodes that never fit
  // are passed over; after a few that do not fit now (each try scans the resident set), none.
  std::uint32_t choose(const Skeleton& skeleton, std::uint32_t lastFinished, double siblingRatio,
                       const NodeTest& pending, const NodeTest& loadable,
                       const std::function<bool(std::uint32_t node, double priority)>& fits,
                       const NodeTest& neverFits);

 private:
  static void set(std::unordered_map<std::uint32_t, double>& set,
                  std::span<const LoadRequest> requests, std::size_t nodeCount);

  std::unordered_map<std::uint32_t, double> wanted_;
  std::unordered_map<std::uint32_t, double> prefetch_;
  std::vector<std::pair<double, std::uint32_t>> order_;  // wanted non-resident, best first
  bool dirty_ = true;
};

}  // namespace hlod
