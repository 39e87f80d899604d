// The fly-around of a CAD scene: a loop around the model's box, outside it (so through nothing),
// low over the ground at the sides' middles and higher at the corners, looking at its centre;
// hlod/runtime/CameraPath.h gives its contract.
#include <algorithm>
#include <cmath>

#include "runtime/paths/PathGenerators.h"

namespace hlod {

Result<CameraPath> makeFlyAroundPath(const Skeleton& skeleton, double duration) {
  if (skeleton.nodes.empty()) return makeError("fly-around: the store has no nodes");
  if (!(duration > 0.0) || !std::isfinite(duration))
    return makeError("fly-around: the duration must be positive");
  const Aabb box = rootBounds(skeleton);
  const int u = int(skeleton.up), a = (u + 1) % 3, b = (u + 2) % 3;
  const glm::dvec3 size = box.size(), centre = box.centre();
  const double margin = 0.15 * std::max(size[a], size[b]) + 1.0;
  const double lo[2] = {box.min[a] - margin, box.min[b] - margin};
  const double hi[2] = {box.max[a] + margin, box.max[b] + margin};
  const double height = std::max(size[u], 0.05 * std::max(size[a], size[b]));
  // Keyframes alternate edge middles (low) and corners (high), all outside the box: the spline
  // stays within the boxes consecutive keyframes span (CameraPath.h), so it never enters the
  // model's.
  const double ea[8] = {0.5, 1.0, 1.0, 1.0, 0.5, 0.0, 0.0, 0.0};
  const double eb[8] = {0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 0.5, 0.0};
  std::vector<CameraKeyframe> keys;
  for (int k = 0; k <= 8; ++k) {
    const int i = k % 8;
    CameraKeyframe key;
    key.time = duration * k / 8.0;
    key.position[a] = lo[0] + (hi[0] - lo[0]) * ea[i];
    key.position[b] = lo[1] + (hi[1] - lo[1]) * eb[i];
    key.position[u] = box.min[u] + height * (i % 2 == 0 ? 0.45 : 1.1);
    key.target = centre;
    key.target[u] = box.min[u] + 0.35 * height;
    key.up = glm::dvec3(0.0);
    key.up[u] = 1.0;
    key.fovY = 60.0;
    keys.push_back(key);
  }
  return CameraPath::fromKeyframes(std::move(keys));
}

}  // namespace hlod
