// The orbit path: a circle around the model's up axis, for any model (a store's bounds, or a
// scene file's camera); hlod/runtime/CameraPath.h gives its contract.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "hlod/runtime/Framing.h"
#include "runtime/Finite.h"
#include "runtime/paths/PathGenerators.h"

namespace hlod {

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

}  // namespace hlod
