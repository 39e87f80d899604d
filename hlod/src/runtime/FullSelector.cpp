#include "hlod/runtime/FullSelector.h"

#include <algorithm>

#include "hlod/runtime/LakhiaSelector.h"

namespace hlod {

FullSelector::FullSelector(const Skeleton& skeleton, const SelectorParams& params)
    : Selector(skeleton, params) {}

Selection FullSelector::select(const View& view, const Residency& residency) {
  Selection s = beginFrame(view);
  const PriorityModel model(view, params_.lakhia);
  const auto& nodes = skeleton_.nodes;

  auto visit = [&](std::uint32_t n) {
    const NodePriority np = model.evaluate(nodes[n]);
    s.loadPriorities.push_back({n, np.priority});
    return np.visible;
  };

  std::vector<std::uint32_t> queue;
  for (std::uint32_t r : candidateRoots(view, s)) {
    if (r < nodes.size() && visit(r) && !occludedNow(r, s)) queue.push_back(r);
  }
  walkFront(
      std::move(queue), residency, s, [](std::uint32_t) { return true; }, visit,
      [](std::uint32_t, const std::vector<std::uint32_t>&) { return true; });
  planDraws(view, s);
  return s;
}

}  // namespace hlod
