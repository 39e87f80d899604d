// The drive path: a loop along a city's outermost inner streets at driving height and speed, its
// corners turned on quarter circles (hlod/runtime/CameraPath.h gives its timing).
#include <algorithm>
#include <cmath>
#include <vector>

#include "runtime/paths/PathGenerators.h"
#include "runtime/paths/Streets.h"

namespace hlod {

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

}  // namespace hlod
