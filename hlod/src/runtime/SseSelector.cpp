#include "hlod/SseSelector.h"

#include <algorithm>
#include <cmath>

#include "hlod/LakhiaSelector.h"

namespace hlod {

SseSelector::SseSelector(const Skeleton& skeleton, const SelectorParams& params)
    : Selector(skeleton, params) {}

double SseSelector::screenSpaceError(const NodeInfo& node, const View& view, double minDistance) {
  const double distance = std::max(minDistance > 0.0 ? minDistance : 1e-6,
                                   distanceToBox(view.camera.position, node.bounds));
  const double e = node.geometricError * view.camera.pixelsPerUnit(distance, view.viewportHeight);
  return std::isfinite(e) ? std::max(0.0, e) : 0.0;
}

Selection SseSelector::select(const View& view, const Residency& residency) {
  Selection s = beginFrame();
  const Frustum frustum = view.camera.frustum();
  const auto& nodes = skeleton_.nodes;
  const double minDistance = params_.lakhia.c_minDistance;
  const double visWeight = 1.0 + std::max(0.0, params_.lakhia.c_vis);

  // Load priority: the screen-space error, divided by (1 + c_vis) outside the frustum, so that
  // the loader fetches what would be refined first and what is just outside view next.
  auto visit = [&](std::uint32_t n, bool visible) {
    const double sse = screenSpaceError(nodes[n], view, minDistance);
    s.loadPriorities.push_back({n, visible ? sse : sse / visWeight});
    return sse;
  };

  std::vector<std::uint32_t> queue;
  for (std::uint32_t r : skeleton_.roots) {
    if (r >= nodes.size()) continue;
    const bool visible = frustum.intersects(nodes[r].bounds);
    visit(r, visible);
    if (visible) queue.push_back(r);
  }
  std::vector<std::uint32_t> children;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::uint32_t n = queue[head];
    const NodeInfo& info = nodes[n];
    const bool hasChildren = info.childCount > 0 && info.firstChild < nodes.size() &&
                             info.childCount <= nodes.size() - info.firstChild;
    if (!hasChildren || screenSpaceError(info, view, minDistance) <= params_.ssePixels) {
      markDrawn(n, s);
      continue;
    }
    children.clear();
    bool allResident = true;
    for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c) {
      const bool visible = frustum.intersects(nodes[c].bounds);
      visit(c, visible);
      if (!visible) continue;
      children.push_back(c);
      allResident = allResident && residency.isResident(c);
    }
    if (!allResident) {
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
