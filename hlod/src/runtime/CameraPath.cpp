// A camera path: keyframes checked at the boundary, sampled by Steffen's monotone spline
// (runtime/SteffenSpline.h) at a time or at frame i of a frame rate. The JSON file is
// CameraPathJson.cpp's, the generators live in runtime/paths/.
#include "hlod/runtime/CameraPath.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "runtime/Finite.h"
#include "runtime/SteffenSpline.h"

namespace hlod {

namespace {

// A number for a message: up to 6 significant digits, 1e+300 style when large.
std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

Result<CameraPath> CameraPath::fromKeyframes(std::vector<CameraKeyframe> keyframes) {
  if (keyframes.size() < 2) {
    return makeError("camera path needs at least 2 keyframes, got " +
                     std::to_string(keyframes.size()));
  }
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    const CameraKeyframe& k = keyframes[i];
    const std::string where = "keyframe " + std::to_string(i);
    if (!std::isfinite(k.time) || !finite(k.position) || !finite(k.target) || !finite(k.up) ||
        !std::isfinite(k.fovY)) {
      return makeError(where + ": values must be finite numbers (NaN or infinity found)");
    }
    if (!(k.fovY > 0.0 && k.fovY < 180.0)) return makeError(where + ": fov must be in (0, 180)");
    if (glm::length(k.target - k.position) <= 0.0) {
      return makeError(where + ": target equals position (no view direction)");
    }
    if (glm::length(k.up) <= 0.0) return makeError(where + ": up is a zero vector");
    if (i > 0 && !(k.time > keyframes[i - 1].time)) {
      return makeError(where + ": times must be strictly increasing (" +
                       std::to_string(keyframes[i - 1].time) + " then " + std::to_string(k.time) +
                       ")");
    }
  }
  const double duration = keyframes.back().time - keyframes.front().time;
  if (!std::isfinite(duration)) {
    return makeError("camera path: the duration from " + std::to_string(keyframes.front().time) +
                     " s to " + std::to_string(keyframes.back().time) + " s is not finite");
  }
  struct Field {
    glm::dvec3 CameraKeyframe::*member;
    const char* name;
  };
  for (const Field f :
       {Field{&CameraKeyframe::position, "position"}, Field{&CameraKeyframe::target, "target"},
        Field{&CameraKeyframe::up, "up"}}) {
    if (!slopesFinite(keyframes, f.member)) {
      return makeError(std::string("camera path: the ") + f.name +
                       " changes too much between two keyframes (its slope is not finite)");
    }
  }
  CameraPath p;
  p.keys_ = std::move(keyframes);
  p.posTangent_ = monotoneTangents(p.keys_, &CameraKeyframe::position);
  p.targetTangent_ = monotoneTangents(p.keys_, &CameraKeyframe::target);
  p.upTangent_ = monotoneTangents(p.keys_, &CameraKeyframe::up);
  return p;
}

CameraSample CameraPath::sample(double t, double aspect, double nearPlane, double farPlane) const {
  if (!std::isfinite(t)) t = startTime();
  t = std::clamp(t, startTime(), endTime());
  // The segment [keys_[i].time, keys_[i+1].time] holding t.
  const auto it = std::upper_bound(keys_.begin(), keys_.end(), t,
                                   [](double v, const CameraKeyframe& k) { return v < k.time; });
  std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, it - keys_.begin() - 1));
  i = std::min(i, keys_.size() - 2);
  const CameraKeyframe& a = keys_[i];
  const CameraKeyframe& b = keys_[i + 1];
  const double h = b.time - a.time;
  const double s = std::clamp((t - a.time) / h, 0.0, 1.0);
  CameraSample out;
  out.time = t;
  Camera& c = out.camera;
  c.position = hermite(a.position, posTangent_[i], b.position, posTangent_[i + 1], h, s);
  c.target = hermite(a.target, targetTangent_[i], b.target, targetTangent_[i + 1], h, s);
  glm::dvec3 up = hermite(a.up, upTangent_[i], b.up, upTangent_[i + 1], h, s);
  c.up = glm::length(up) > 1e-12 ? glm::normalize(up) : glm::normalize(a.up);
  if (glm::length(c.target - c.position) <= 1e-12) c.target = c.position + (b.target - b.position);
  c.fovY = a.fovY + (b.fovY - a.fovY) * s;
  c.aspect = aspect;
  c.nearPlane = nearPlane;
  c.farPlane = farPlane;
  out.velocity =
      hermiteDerivative(a.position, posTangent_[i], b.position, posTangent_[i + 1], h, s);
  return out;
}

Result<std::uint64_t> CameraPath::frameCount(double fps, std::uint64_t maxFrames) const {
  if (!(fps > 0.0) || !std::isfinite(fps)) {
    return makeError("camera path: the frame rate must be a positive number (got " +
                     formatNumber(fps) + ")");
  }
  // A product a rounding error below an integer (0.6 s at 10 fps is 5.999...) counts that frame;
  // the frame then lies a rounding error past the end and samples the end.
  const double intervals = duration() * fps;
  const double last = std::floor(intervals * (1.0 + 1e-12));
  // last < maxFrames, in double, also keeps the cast below in range.
  if (!std::isfinite(last) || !(last < static_cast<double>(maxFrames))) {
    return makeError("camera path: " + formatNumber(duration()) + " s at " + formatNumber(fps) +
                     " fps gives " + formatNumber(last + 1.0) + " frames, more than the " +
                     std::to_string(maxFrames) + " allowed");
  }
  return static_cast<std::uint64_t>(last) + 1;
}

CameraSample CameraPath::sampleFrame(std::uint64_t i, double fps, double aspect) const {
  return sample(startTime() + static_cast<double>(i) / fps, aspect);
}

std::vector<CameraSample> CameraPath::sampleAt(double fps, double aspect,
                                               std::uint64_t maxFrames) const {
  std::vector<CameraSample> out;
  const Result<std::uint64_t> frames = frameCount(fps, maxFrames);
  if (!frames) return out;
  out.reserve(*frames);
  for (std::uint64_t i = 0; i < *frames; ++i) out.push_back(sampleFrame(i, fps, aspect));
  return out;
}

Result<CameraPath> withDuration(const CameraPath& path, double seconds) {
  if (!(seconds > 0.0) || !std::isfinite(seconds))
    return makeError("a path's duration must be a positive number of seconds");
  auto keys = path.keyframes();
  const double t0 = path.startTime(), scale = seconds / path.duration();
  for (auto& k : keys) k.time = t0 + (k.time - t0) * scale;
  return CameraPath::fromKeyframes(std::move(keys));
}

}  // namespace hlod
