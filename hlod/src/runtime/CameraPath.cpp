// Camera paths: monotone cubic Hermite interpolation of keyframes after M. Steffen, "A simple
// method for monotonic interpolation in one dimension" (Astron. Astrophys. 239, 1990), and the
// path generators of the Lakhia walk-fly (shared/seeds/lakhia-hlod.txt, Fig. 7), drive and orbit.
#include "hlod/runtime/CameraPath.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hlod/runtime/Framing.h"

namespace hlod {

namespace {

using nlohmann::json;

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Steffen's tangent at an interior keyframe from the slopes dl (over an interval hl) on its left
// and dr (over hr) on its right: the slope of the parabola through the three keyframes, limited
// to twice the smaller slope, and 0 at a turn or beside a flat interval. Tangents of the slope's
// sign and at most twice it at both ends of an interval keep the cubic monotone there, so it
// stays between its two keyframe values (Steffen 1990).
double steffenInterior(double dl, double dr, double hl, double hr) {
  if (dl == 0.0 || dr == 0.0 || (dl > 0.0) != (dr > 0.0)) return 0.0;
  const double w = hl / (hl + hr);
  const double parabola = dl * (1.0 - w) + dr * w;
  return std::copysign(2.0 * std::min({std::abs(dl), std::abs(dr), 0.5 * std::abs(parabola)}), dr);
}

// Steffen's tangent at an end keyframe, slope d0 over h0 next to it and d1 over h1 after that:
// the end slope of the parabola through the three end keyframes, limited in the same way
// (Steffen 1990). The same formula serves both ends (it is odd in the slopes).
double steffenEnd(double d0, double d1, double h0, double h1) {
  const double w = h0 / (h0 + h1);
  const double parabola = d0 * (1.0 + w) - d1 * w;
  if (d0 == 0.0 || parabola == 0.0 || (parabola > 0.0) != (d0 > 0.0)) return 0.0;
  return std::abs(parabola) > 2.0 * std::abs(d0) ? 2.0 * d0 : parabola;
}

// A field whose last keyframe repeats its first, up to rounding (an orbit's angle 2 pi), is a
// loop: its ends get the tangent of an interior keyframe between the last and the first
// interval, so that the loop is C1 across the seam as everywhere else.
bool isLoop(const std::vector<CameraKeyframe>& k, glm::dvec3 CameraKeyframe::*field) {
  if (k.size() < 3) return false;
  double extent = 0.0;
  for (const CameraKeyframe& key : k) {
    extent = std::max(extent, glm::length(key.*field - k.front().*field));
  }
  return extent > 0.0 && glm::length(k.back().*field - k.front().*field) <= 1e-9 * extent;
}

// Per-component monotone tangents (Steffen 1990) at every keyframe; C1 at the keyframes.
std::vector<glm::dvec3> monotoneTangents(const std::vector<CameraKeyframe>& k,
                                         glm::dvec3 CameraKeyframe::*field) {
  const std::size_t n = k.size();
  std::vector<double> h(n - 1);
  std::vector<glm::dvec3> d(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    h[i] = k[i + 1].time - k[i].time;
    d[i] = (k[i + 1].*field - k[i].*field) / h[i];
  }
  std::vector<glm::dvec3> m(n);
  if (n == 2) {
    m[0] = m[1] = d[0];  // a straight line
    return m;
  }
  const bool loop = isLoop(k, field);
  for (int c = 0; c < 3; ++c) {
    for (std::size_t i = 1; i + 1 < n; ++i) {
      m[i][c] = steffenInterior(d[i - 1][c], d[i][c], h[i - 1], h[i]);
    }
    if (loop) {
      m[0][c] = m[n - 1][c] = steffenInterior(d[n - 2][c], d[0][c], h[n - 2], h[0]);
    } else {
      m[0][c] = steffenEnd(d[0][c], d[1][c], h[0], h[1]);
      m[n - 1][c] = steffenEnd(d[n - 2][c], d[n - 3][c], h[n - 2], h[n - 3]);
    }
  }
  return m;
}

// True when every interval's change of `field` and its slope are finite with room to spare, so
// that the tangents (at most 3 slopes) and the Hermite terms cannot overflow.
bool slopesFinite(const std::vector<CameraKeyframe>& k, glm::dvec3 CameraKeyframe::*field) {
  for (std::size_t i = 0; i + 1 < k.size(); ++i) {
    const glm::dvec3 change = k[i + 1].*field - k[i].*field;
    if (!finite(4.0 * change) || !finite(4.0 * change / (k[i + 1].time - k[i].time))) {
      return false;
    }
  }
  return true;
}

glm::dvec3 hermite(const glm::dvec3& p0, const glm::dvec3& m0, const glm::dvec3& p1,
                   const glm::dvec3& m1, double h, double s) {
  const double s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * h * m0 + (-2 * s3 + 3 * s2) * p1 +
         (s3 - s2) * h * m1;
}

glm::dvec3 hermiteDerivative(const glm::dvec3& p0, const glm::dvec3& m0, const glm::dvec3& p1,
                             const glm::dvec3& m1, double h, double s) {
  const double s2 = s * s;
  return ((6 * s2 - 6 * s) * p0 + (3 * s2 - 4 * s + 1) * h * m0 + (-6 * s2 + 6 * s) * p1 +
          (3 * s2 - 2 * s) * h * m1) /
         h;
}

Result<glm::dvec3> readVec3(const json& j, const char* key, std::size_t index) {
  const std::string where = "keyframe " + std::to_string(index) + ": \"" + key + "\"";
  if (!j.contains(key)) return makeError(where + " is missing");
  const json& v = j.at(key);
  if (!v.is_array() || v.size() != 3) return makeError(where + " must be an array of 3 numbers");
  glm::dvec3 out;
  for (int i = 0; i < 3; ++i) {
    if (!v[i].is_number()) return makeError(where + " must be an array of 3 numbers");
    out[i] = v[i].get<double>();
  }
  return out;
}

// A number for a message: up to 6 significant digits, 1e+300 style when large.
std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

json toJson(const glm::dvec3& v) {
  return json::array({v.x, v.y, v.z});
}

// Street centres along one axis: gaps between the merged [lo, hi] intervals of the block boxes,
// and lines where one block's box ends exactly where another's begins (blocks whose ground
// reaches the middle of the street, as the procedural city's do, meet there).
std::vector<double> streetsAlong(const Skeleton& sk, int axis, double minGap) {
  std::vector<std::pair<double, double>> iv;
  for (std::uint32_t r : sk.blockRoots()) {
    if (r >= sk.nodes.size() || sk.nodes[r].bounds.empty()) continue;
    iv.push_back({sk.nodes[r].bounds.min[axis], sk.nodes[r].bounds.max[axis]});
  }
  std::sort(iv.begin(), iv.end());
  std::vector<double> centres;
  double hi = iv.empty() ? 0.0 : iv.front().second;
  for (std::size_t i = 1; i < iv.size(); ++i) {
    if (iv[i].first - hi >= minGap) centres.push_back((iv[i].first + hi) * 0.5);
    hi = std::max(hi, iv[i].second);
  }
  if (!centres.empty()) return centres;
  constexpr double kTouch = 0.05;  // metres
  std::vector<double> ends;
  for (const auto& a : iv) ends.push_back(a.second);
  std::sort(ends.begin(), ends.end());
  for (const auto& a : iv) {
    const auto it = std::lower_bound(ends.begin(), ends.end(), a.first - kTouch);
    if (it == ends.end() || *it > a.first + kTouch) continue;
    if (!centres.empty() && a.first - centres.back() <= minGap) continue;
    // A line some other block crosses (e.g. the middle of a cell's courtyard) is no street.
    const bool crossed = std::any_of(iv.begin(), iv.end(), [&](const auto& b) {
      return b.first < a.first - kTouch && b.second > a.first + kTouch;
    });
    if (!crossed) centres.push_back(a.first);
  }
  return centres;
}

Aabb rootBounds(const Skeleton& sk) {
  Aabb all;
  for (std::uint32_t r : sk.roots) {
    if (r < sk.nodes.size()) all.extend(sk.nodes[r].bounds);
  }
  return all;
}

constexpr double kMinStreet = 3.0;  // metres: narrower gaps are not streets

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

Result<CameraPath> CameraPath::parse(std::string_view text) {
  json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return makeError("camera path: malformed JSON");
  const json* list = &j;
  if (j.is_object()) {
    if (!j.contains("keyframes")) return makeError("camera path: no \"keyframes\" array");
    list = &j.at("keyframes");
  }
  if (!list->is_array()) return makeError("camera path: \"keyframes\" must be an array");
  std::vector<CameraKeyframe> keys;
  for (std::size_t i = 0; i < list->size(); ++i) {
    const json& k = (*list)[i];
    const std::string where = "keyframe " + std::to_string(i);
    if (!k.is_object()) return makeError(where + " must be an object");
    CameraKeyframe kf;
    if (!k.contains("time") || !k.at("time").is_number()) {
      return makeError(where + ": \"time\" must be a number");
    }
    kf.time = k.at("time").get<double>();
    auto pos = readVec3(k, "position", i);
    if (!pos) return pos.error();
    auto tgt = readVec3(k, "target", i);
    if (!tgt) return tgt.error();
    kf.position = *pos;
    kf.target = *tgt;
    if (k.contains("up")) {
      auto up = readVec3(k, "up", i);
      if (!up) return up.error();
      kf.up = *up;
    }
    if (k.contains("fov")) {
      if (!k.at("fov").is_number()) return makeError(where + ": \"fov\" must be a number");
      kf.fovY = k.at("fov").get<double>();
    }
    keys.push_back(kf);
  }
  return fromKeyframes(std::move(keys));
}

Result<CameraPath> CameraPath::read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError("cannot open camera path '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  auto p = parse(ss.str());
  if (!p) return makeError(path + ": " + p.message());
  return p;
}

std::string CameraPath::toJson() const {
  json keys = json::array();
  for (const CameraKeyframe& k : keys_) {
    keys.push_back({{"time", k.time},
                    {"position", hlod::toJson(k.position)},
                    {"target", hlod::toJson(k.target)},
                    {"up", hlod::toJson(k.up)},
                    {"fov", k.fovY}});
  }
  return json{{"keyframes", keys}}.dump(2);
}

Status CameraPath::write(const std::string& path) const {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return makeError("cannot write camera path '" + path + "'");
  out << toJson() << '\n';
  if (!out) return makeError("error writing camera path '" + path + "'");
  return Ok{};
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

namespace {

// A circle around the up axis through `centre`: radius `rho` in the horizontal plane, `height`
// above centre, starting at `azimuth0` (radians from horizontalAxes' first axis towards the
// second) and looking at centre, once round in `duration`. Keyframes every 7.5 degrees from the
// start plus the four extremes along the two horizontal axes: the spline never passes beyond its
// keyframes' coordinates, so the extremes must be keyframes, and at this spacing the radius stays
// within 1e-5 and the speed within 0.3% of the circle's.
Result<CameraPath> orbitCircle(const glm::dvec3& centre, double rho, double height, double azimuth0,
                               UpAxis up, double fovY, double duration) {
  glm::dvec3 first, second;
  horizontalAxes(up, first, second);
  const double turn = 2.0 * std::numbers::pi;
  const int n = 48;
  std::vector<double> angles;  // from the start, in [0, turn)
  for (int i = 0; i < n; ++i) angles.push_back(turn * i / n);
  for (int k = 0; k < 4; ++k) {
    double a = std::fmod(k * turn / 4 - azimuth0, turn);
    if (a < 0.0) a += turn;
    angles.push_back(a >= turn - 1e-9 ? 0.0 : a);
  }
  std::sort(angles.begin(), angles.end());
  angles.erase(
      std::unique(angles.begin(), angles.end(), [](double l, double r) { return r - l < 1e-9; }),
      angles.end());
  std::vector<CameraKeyframe> keys;
  for (double a : angles) {
    const double az = azimuth0 + a;
    CameraKeyframe k;
    k.time = duration * a / turn;
    k.position =
        centre + rho * (std::cos(az) * first + std::sin(az) * second) + height * upVector(up);
    k.target = centre;
    k.up = upVector(up);
    k.fovY = fovY;
    keys.push_back(k);
  }
  // The last keyframe repeats the first exactly: a loop, C1 at the seam.
  keys.push_back(keys.front());
  keys.back().time = duration;
  return CameraPath::fromKeyframes(std::move(keys));
}

}  // namespace

Result<CameraPath> makeOrbitPath(const Skeleton& sk, double duration, double fovY, double aspect) {
  const Aabb b = rootBounds(sk);
  if (b.empty()) return makeError("orbit path: the model has no hlod_0 bounds");
  if (!(duration > 0.0)) duration = 30.0;
  fovY = std::clamp(fovY, 1.0, 170.0);
  if (!(aspect > 0.0)) aspect = 16.0 / 9.0;
  const double r = std::max(1e-3, 0.5 * glm::length(b.size()));
  const double dist = framingDistance(r, fovY, aspect);
  const double elevation = glm::radians(30.0);
  return orbitCircle(b.centre(), dist * std::cos(elevation), dist * std::sin(elevation), 0.0, sk.up,
                     fovY, duration);
}

Result<CameraPath> makeOrbitPathFrom(const Camera& start, UpAxis up, double duration) {
  if (!finite(start.position) || !finite(start.target) || !(start.fovY > 0.0 && start.fovY < 180.0))
    return makeError("orbit path: the start camera is not finite");
  if (!(duration > 0.0) || !std::isfinite(duration)) duration = 30.0;
  glm::dvec3 first, second;
  horizontalAxes(up, first, second);
  const glm::dvec3 offset = start.position - start.target;
  const double x = glm::dot(offset, first), y = glm::dot(offset, second);
  const double rho = std::hypot(x, y);
  if (!(rho > 1e-9 * std::max(1.0, glm::length(offset))))
    return makeError(
        "orbit path: the camera looks along the up axis, so there is no circle "
        "around its target to follow");
  return orbitCircle(start.target, rho, glm::dot(offset, upVector(up)), std::atan2(y, x), up,
                     start.fovY, duration);
}

namespace {

// The street generators read the model as a z-up city (streets in X and Y, heights in Z).
Status requireZUp(const char* kind, const Skeleton& sk) {
  if (sk.up == UpAxis::Z) return Ok{};
  return makeError(std::string(kind) + " path: defined for z-up cities, and this store is " +
                   upAxisName(sk.up) + "-up (use --kind orbit, or rebuild with --up z if the " +
                   "model is a city)");
}

}  // namespace

Result<CameraPath> makeWalkFlyPath(const Skeleton& sk) {
  if (auto z = requireZUp("walk-fly", sk); !z) return z.error();
  const Aabb b = rootBounds(sk);
  if (b.empty()) return makeError("walk-fly path: the model has no hlod_0 bounds");
  const glm::dvec3 size = b.size();
  const glm::dvec3 c = b.centre();
  const double eye = b.min.z + 1.7;
  // Walk along the street (a gap in X, running along Y) nearest the centre; outside the model
  // when there is none.
  std::vector<double> xs = streetsAlong(sk, 0, kMinStreet);
  double sx = b.min.x - 3.0;
  for (double x : xs) {
    if (std::abs(x - c.x) < std::abs(sx - c.x)) sx = x;
  }
  const double walkSpeed = 2.0;  // m/s, a brisk walk
  const double y0 = b.min.y - 2.0;
  const double flyHeight = b.max.z + 0.8 * std::max(size.x, size.y);
  std::vector<CameraKeyframe> keys;
  auto key = [&](double t, glm::dvec3 p, glm::dvec3 target) {
    CameraKeyframe k;
    k.time = t;
    k.position = p;
    k.target = target;
    keys.push_back(k);
  };
  // 0-15 s: walk, looking ahead along the street.
  for (double t : {0.0, 5.0, 10.0, 15.0}) {
    const double y = y0 + walkSpeed * t;
    key(t, {sx, y, eye}, {sx, y + 30.0, eye});
  }
  const double yw = y0 + walkSpeed * 15.0;
  // 15-30 s: rise while moving on, the view tilting down to the model centre. The heights follow
  // an ease-in-out (smoothstep) from eye height at 15 s to the fly height at 30 s, so that the
  // climb sets off gently from the walk instead of shooting up to a fixed share of the height.
  const auto climb = [&](double t) {
    const double u = (t - 15.0) / 15.0;
    return eye + (flyHeight - eye) * u * u * (3.0 - 2.0 * u);
  };
  key(19.0, {sx, yw + 12.0, climb(19.0)}, {sx, yw + 60.0, b.min.z});
  key(24.0, {sx, c.y - 0.35 * size.y, climb(24.0)}, {c.x, c.y, b.min.z});
  // Then across the whole model at the fly height.
  key(30.0, {c.x + 0.2 * size.x, c.y, flyHeight}, {c.x, c.y + 0.1 * size.y, b.min.z});
  key(35.0, {c.x + 0.35 * size.x, c.y + 0.4 * size.y, flyHeight},
      {c.x, c.y + 0.2 * size.y, b.min.z});
  return CameraPath::fromKeyframes(std::move(keys));
}

Result<CameraPath> makeDrivePath(const Skeleton& sk) {
  if (auto z = requireZUp("drive", sk); !z) return z.error();
  const Aabb b = rootBounds(sk);
  if (b.empty()) return makeError("drive path: the model has no hlod_0 bounds");
  const double height = b.min.z + 1.5;
  std::vector<double> xs = streetsAlong(sk, 0, kMinStreet);
  std::vector<double> ys = streetsAlong(sk, 1, kMinStreet);
  // A rectangular loop on the outermost inner streets (or just outside the model).
  const double x0 = xs.size() >= 2 ? xs.front() : b.min.x - 4.0;
  const double x1 = xs.size() >= 2 ? xs.back() : (xs.size() == 1 ? xs.front() : b.max.x + 4.0);
  const double y0 = ys.size() >= 2 ? ys.front() : b.min.y - 4.0;
  const double y1 = ys.size() >= 2 ? ys.back() : (ys.size() == 1 ? ys.front() : b.max.y + 4.0);
  std::vector<glm::dvec3> corners = {
      {x0, y0, height}, {x1, y0, height}, {x1, y1, height}, {x0, y1, height}};
  double loop = 0.0;
  for (int i = 0; i < 4; ++i) loop += glm::length(corners[(i + 1) % 4] - corners[i]);
  if (!(loop > 1.0)) return makeError("drive path: the model is too small for streets");
  const double speed = 17.0;  // m/s, about 60 km/h
  const double duration = std::clamp(loop / speed, 20.0, 40.0);
  const double length = duration * speed;
  // Keyframes every 10 m along the loop, turning each corner on a quarter circle of radius
  // `round` metres. The arc has keyframes every 30 degrees, timed by their distance like the
  // rest: its ends are where it is extreme in X and Y, so the monotone spline follows it at an
  // even speed instead of cutting across.
  const double round = std::min(8.0, 0.25 * std::min(std::abs(x1 - x0), std::abs(y1 - y0)));
  std::vector<glm::dvec3> pts;
  for (int i = 0; i < 4; ++i) {
    const glm::dvec3 a = corners[i], bb = corners[(i + 1) % 4];
    const double len = glm::length(bb - a);
    if (!(len > 1e-9)) continue;
    const glm::dvec3 d = (bb - a) / len;
    const double usable = std::max(0.0, len - 2.0 * round);
    const int segments = std::max(1, static_cast<int>(std::ceil(usable / 10.0)));
    for (int k = 0; k <= segments; ++k) pts.push_back(a + d * (round + usable * k / segments));
    const glm::dvec3 next = corners[(i + 2) % 4] - bb;
    if (round > 1e-9 && glm::length(next) > 1e-9) {
      const glm::dvec3 d2 = glm::normalize(next);
      const glm::dvec3 centre = bb - d * round + d2 * round;
      for (double deg : {30.0, 60.0}) {
        const double th = glm::radians(deg);
        pts.push_back(centre + round * (-d2 * std::cos(th) + d * std::sin(th)));
      }
    }
  }
  std::vector<CameraKeyframe> keys;
  double t = 0.0, travelled = 0.0;
  for (std::size_t i = 0;; ++i) {
    const glm::dvec3 p = pts[i % pts.size()];
    const glm::dvec3 next = pts[(i + 1) % pts.size()];
    if (i > 0) {
      const double step = glm::length(p - pts[(i - 1) % pts.size()]);
      if (step <= 1e-9) continue;
      if (travelled + step > length) break;
      travelled += step;
      t += step / speed;
    }
    CameraKeyframe k;
    k.time = t;
    k.position = p;
    k.target = p + glm::normalize(next - p) * 20.0;
    keys.push_back(k);
    if (keys.size() > 10000) break;
  }
  return CameraPath::fromKeyframes(std::move(keys));
}

Result<CameraPath> makeCameraPath(std::string_view kind, const Skeleton& skeleton) {
  if (kind == "walk-fly") return makeWalkFlyPath(skeleton);
  if (kind == "drive") return makeDrivePath(skeleton);
  if (kind == "orbit") return makeOrbitPath(skeleton);
  return makeError("unknown camera path '" + std::string(kind) +
                   "' (known: walk-fly, drive, orbit)");
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
