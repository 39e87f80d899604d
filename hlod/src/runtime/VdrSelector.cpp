// View-dependent rendering under the frame budget (Manocha sec. 5.1; Hoppe 1997's regulation
// driven by Lakhia's v_time loop). See hlod/runtime/VdrSelector.h.
#include "hlod/runtime/VdrSelector.h"

#include <chrono>

namespace hlod {

VdrSelector::VdrSelector(vdr::VdrRuntime& runtime, const SelectorParams& params,
                         const VdrSelectorParams& vdr)
    : Selector(runtime.skeleton(), params), runtime_(runtime), vdr_(vdr), control_(vdr.bound) {}

Selection VdrSelector::select(const View& view, const Residency& /*everything is in memory*/) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  Selection s = beginFrame(view);
  const double target = s.vTime > 0.0 ? s.drawBudgetMs / s.vTime : 0.0;
  const vdr::ErrorProjection projection =
      vdr::ErrorProjection::of(view.camera, view.viewportHeight);
  const Frustum frustum = view.camera.frustum();
  vdr::RefineCounters counters = runtime_.refine(projection, control_.bound());
  double cost = 0.0;
  std::vector<std::uint32_t> front = runtime_.visibleClusters(frustum, &cost);
  for (int i = 0; i < vdr_.corrections && !control_.meets(cost, target); ++i) {
    const double before = control_.bound();
    if (control_.step(cost, target) == before) break;
    const vdr::RefineCounters more = runtime_.refine(projection, control_.bound());
    counters.splits += more.splits;
    counters.forcedSplits += more.forcedSplits;
    counters.collapses += more.collapses;
    front = runtime_.visibleClusters(frustum, &cost);
  }
  for (std::uint32_t c : front) markDrawn(c, s);
  planDraws(view, s);
  s.vertexSplits = counters.splits;
  s.edgeCollapses = counters.collapses;
  s.activeClusters = runtime_.activeClusterCount();
  s.errorBoundPx = control_.bound();
  runtime_.addRefineMs(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  return s;
}

}  // namespace hlod
