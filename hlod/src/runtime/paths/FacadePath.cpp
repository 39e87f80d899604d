// The facade path: a slow walk close to one side of a city street, looking obliquely at the
// facades on that side, which recede from a few metres away to the street's far end. The case of
// Lakhia et al. Fig. 1 (shared/seeds/lakhia-hlod.txt): "consider a slanted view of a building
// facade ... a coarse representation of the object is ideal for the portion of the object that
// is far away from the camera but is too coarse near the camera", where one static level per
// node cannot be right at both ends and view-dependent refinement can.
#include <cmath>
#include <vector>

#include "runtime/paths/PathGenerators.h"
#include "runtime/paths/Streets.h"

namespace hlod {

Result<CameraPath> makeFacadePath(const Skeleton& sk) {
  if (auto z = requireZUp("facade", sk); !z) return z.error();
  const Aabb b = rootBounds(sk);
  if (b.empty()) return makeError("facade path: the model has no hlod_0 bounds");
  const glm::dvec3 c = b.centre();
  // The walk-fly's street (a gap in X running along Y, nearest the centre), 6 m east of its
  // middle: the procedural city's streets are 18-32 m wide, so the east facades stand 3-10 m
  // away (and further by a setback of up to 2.5 m).
  const std::vector<double> xs = streetsAlong(sk, 0, kMinStreet);
  double sx = b.min.x - 3.0;
  for (double x : xs)
    if (std::abs(x - c.x) < std::abs(sx - c.x)) sx = x;
  const double x = sx + 6.0;
  const double eye = b.min.z + 1.7;
  const double y0 = b.min.y + 0.25 * (b.max.y - b.min.y);
  const double speed = 1.5;  // m/s: a slow walk
  // Looking 30 degrees off the street towards the east facades.
  const glm::dvec3 look(std::sin(glm::radians(30.0)), std::cos(glm::radians(30.0)), 0.0);
  std::vector<CameraKeyframe> keys;
  for (double t : {0.0, 2.5, 5.0, 7.5, 10.0}) {
    CameraKeyframe k;
    k.time = t;
    k.position = {x, y0 + speed * t, eye};
    k.target = k.position + 30.0 * look;
    keys.push_back(k);
  }
  return CameraPath::fromKeyframes(std::move(keys));
}

}  // namespace hlod
