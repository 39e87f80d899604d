#pragma once
// When occlusion culling pays (`--occlusion auto`). Culling costs the box pass of its queries
// and saves the drawing of the nodes it finds hidden; from the air almost nothing is hidden and
// the pass would only take budget from the front. The rule compares the two each frame:
//   saved = v_time x frontDraws x the cost (eq. 1) of the occluded nodes at their own level
//           (a lower bound: had they been visible, the walk might have refined them),
//   spent = the box pass's measured ms,
// both low-passed (exponential, weight c_gain). After c_settleFrames frames of culling it is
// turned off while spent > c_margin x saved, for c_offFrames frames; then it runs again from a
// fresh state (OcclusionCulling::reset: the first frame back draws everything). The per-draw
// queries cost no fill (the nodes are drawn anyway) and are not counted in spent.
#include <cstdint>
#include <string_view>

#include "hlod/Result.h"

namespace hlod {

enum class OcclusionMode { Off, On, Auto };
std::string_view occlusionModeName(OcclusionMode mode);  // "off", "on", "auto"
Result<OcclusionMode> parseOcclusionMode(std::string_view name);

struct OcclusionAutoParams {
  double c_gain = 0.2;
  std::uint32_t c_settleFrames = 6;
  std::uint32_t c_offFrames = 30;
  double c_margin = 1.0;
};

class OcclusionAuto {
 public:
  explicit OcclusionAuto(OcclusionMode mode = OcclusionMode::Auto,
                         const OcclusionAutoParams& params = {});
  // Whether the coming frame culls. A true that follows false means: start from a fresh state.
  bool active() const;
  // After a frame: whether it culled, and its saved and spent ms (see above).
  void update(bool culled, double savedMs, double spentMs);
  OcclusionMode mode() const { return mode_; }
  double savedMs() const { return saved_; }
  double spentMs() const { return spent_; }

 private:
  OcclusionMode mode_;
  OcclusionAutoParams params_;
  double saved_ = 0.0, spent_ = 0.0;
  std::uint32_t onFrames_ = 0;   // consecutive culled frames
  std::uint32_t offFrames_ = 0;  // frames left off
};

}  // namespace hlod
