// Camera prediction for prefetching (Manocha sec. 5.3): see hlod/runtime/MotionPredictor.h.
#include "hlod/runtime/MotionPredictor.h"

#include <cmath>

namespace hlod {

void MotionPredictor::observe(const CameraSample& s) {
  const double dt = s.time - last_.time;
  if (frames_ == 0 || !(dt > 0.0 && dt <= params_.c_maxGap)) {
    frames_ = 1;
    velocity_ = turn_ = glm::dvec3(0.0);
    last_ = s;
    return;
  }
  const glm::dvec3 v = (s.camera.position - last_.camera.position) / dt;
  const glm::dvec3 w = (s.camera.forward() - last_.camera.forward()) / dt;
  const double a = frames_ == 1 ? 1.0 : params_.c_smooth;
  velocity_ += a * (v - velocity_);
  turn_ += a * (w - turn_);
  last_ = s;
  ++frames_;
}

std::optional<CameraSample> MotionPredictor::predict() const {
  if (frames_ < 2) return std::nullopt;
  const double t = params_.c_ahead;
  if (glm::length(velocity_) * t < 1e-9 && glm::length(turn_) * t < 1e-6) return std::nullopt;
  CameraSample p = last_;
  p.time = last_.time + t;
  p.velocity = velocity_;
  p.camera.position = last_.camera.position + velocity_ * t;
  glm::dvec3 dir = last_.camera.forward() + turn_ * t;
  if (!(glm::length(dir) > 1e-9)) dir = last_.camera.forward();
  const double distance = std::max(glm::length(last_.camera.target - last_.camera.position), 1e-6);
  p.camera.target = p.camera.position + glm::normalize(dir) * distance;
  p.camera.fovY = std::min(170.0, last_.camera.fovY * (1.0 + params_.c_widen));
  return p;
}

}  // namespace hlod
