#include "hlod/runtime/SseSelector.h"

#include <algorithm>
#include <cmath>

#include "hlod/runtime/LakhiaSelector.h"

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
  Selection s = beginFrame(view);
  const Frustum frustum = view.camera.frustum();
  const auto& nodes = skeleton_.nodes;
  const double minDistance = params_.lakhia.c_minDistance;
  const double visWeight = 1.0 + std::max(0.0, params_.lakhia.c_vis);

  // Load priority: the screen-space error, divided by (1 + c_vis) outside the frustum, so that
  // the loader fetches what would be refined first and what is just outside view next.
  auto visit = [&](std::uint32_t n) {
    const bool visible = frustum.intersects(nodes[n].bounds);
    const double sse = screenSpaceError(nodes[n], view, minDistance);
    s.loadPriorities.push_back({n, visible ? sse : sse / visWeight});
    return visible;
  };

  std::vector<std::uint32_t> queue;
  for (std::uint32_t r : candidateRoots(view, s)) {
    if (r < nodes.size() && visit(r) && !occludedNow(r, s)) queue.push_back(r);
  }
  // Refine while the projected geometric error exceeds ssePixels.
  walkFront(
      std::move(queue), residency, s,
      [&](std::uint32_t n) {
        return screenSpaceError(nodes[n], view, minDistance) > params_.ssePixels;
      },
      visit, [](std::uint32_t, const std::vector<std::uint32_t>&) { return true; });
  planDraws(view, s);
  return s;
}

}  // namespace hlod
