#include "hlod/FullSelector.h"

#include <algorithm>

#include "hlod/LakhiaSelector.h"

namespace hlod {

FullSelector::FullSelector(const Skeleton& skeleton, const SelectorParams& params)
    : Selector(skeleton, params) {}

Selection FullSelector::select(const View& view, const Residency& residency) {
  Selection s = beginFrame();
  const PriorityModel model(view, params_.lakhia);
  const auto& nodes = skeleton_.nodes;

  auto visit = [&](std::uint32_t n) {
    const NodePriority np = model.evaluate(nodes[n]);
    s.loadPriorities.push_back({n, np.priority});
    return np.visible;
  };

  std::vector<std::uint32_t> queue;
  for (std::uint32_t r : skeleton_.roots) {
    if (r < nodes.size() && visit(r)) queue.push_back(r);
  }
  std::vector<std::uint32_t> children;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::uint32_t n = queue[head];
    const NodeInfo& info = nodes[n];
    if (info.childCount == 0 || info.firstChild >= nodes.size() ||
        info.childCount > nodes.size() - info.firstChild) {
      markDrawn(n, s);
      continue;
    }
    children.clear();
    for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c) {
      if (visit(c)) children.push_back(c);
    }
    if (!std::all_of(children.begin(), children.end(),
                     [&](std::uint32_t c) { return residency.isResident(c); })) {
      ++s.coarserBecauseNotResident;
      markDrawn(n, s);
      continue;
    }
    markRefined(n, s);
    queue.insert(queue.end(), children.begin(), children.end());
  }
  finishFrame(s);
  return s;
}

}  // namespace hlod
