// `--occlusion auto`: see hlod/runtime/OcclusionAuto.h.
#include "hlod/runtime/OcclusionAuto.h"

#include <cassert>
#include <cmath>
#include <string>

namespace hlod {

std::string_view occlusionModeName(OcclusionMode mode) {
  switch (mode) {
    case OcclusionMode::Off:
      return "off";
    case OcclusionMode::On:
      return "on";
    case OcclusionMode::Auto:
      return "auto";
  }
  return "auto";
}

Result<OcclusionMode> parseOcclusionMode(std::string_view name) {
  for (OcclusionMode m : {OcclusionMode::Off, OcclusionMode::On, OcclusionMode::Auto})
    if (occlusionModeName(m) == name) return m;
  return makeError("occlusion must be on, off or auto, not '" + std::string(name) + "'");
}

OcclusionAuto::OcclusionAuto(OcclusionMode mode, const OcclusionAutoParams& params)
    : mode_(mode), params_(params) {
  assert(params_.c_gain > 0.0 && params_.c_gain <= 1.0);
}

bool OcclusionAuto::active() const {
  if (mode_ != OcclusionMode::Auto) return mode_ == OcclusionMode::On;
  return offFrames_ == 0;
}

void OcclusionAuto::update(bool culled, double savedMs, double spentMs) {
  if (mode_ != OcclusionMode::Auto) return;
  if (!culled) {
    if (offFrames_ > 0) --offFrames_;
    onFrames_ = 0;
    return;
  }
  const double g = onFrames_ == 0 ? 1.0 : params_.c_gain;
  saved_ += g * ((std::isfinite(savedMs) ? savedMs : 0.0) - saved_);
  spent_ += g * ((std::isfinite(spentMs) ? spentMs : 0.0) - spent_);
  ++onFrames_;
  if (onFrames_ >= params_.c_settleFrames && spent_ > params_.c_margin * saved_) {
    offFrames_ = params_.c_offFrames;
    onFrames_ = 0;
  }
}

}  // namespace hlod
