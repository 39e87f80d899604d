// The walk-fly path of Lakhia et al. (shared/seeds/lakhia-hlod.txt, Fig. 7): a walk at eye
// height along the street nearest the model's centre, rising into a fly-over of the whole model
// (hlod/runtime/CameraPath.h gives its timing).
#include <cmath>
#include <vector>

#include "runtime/paths/PathGenerators.h"
#include "runtime/paths/Streets.h"

namespace hlod {

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

}  // namespace hlod
