#pragma once
// Screen-space-error selection (Erikson et al. HLODs; Cesium 3D Tiles): refine a node while its
// geometricError projected at its distance exceeds ssePixels, with frustum culling and the same
// residency rule as Lakhia (a visible child not resident keeps its parent on the front). No time
// budget: estimatedMs is reported from the same v_time estimate, for the statistics.
#include "hlod/runtime/Selector.h"

namespace hlod {

class SseSelector final : public Selector {
 public:
  SseSelector(const Skeleton& skeleton, const SelectorParams& params = {});
  std::string_view name() const override { return "sse"; }
  Selection select(const View& view, const Residency& residency) override;

  // geometricError * pixels per unit at max(c_minDistance, distance camera-box).
  static double screenSpaceError(const NodeInfo& node, const View& view, double minDistance);
};

}  // namespace hlod
