#include "hlod/runtime/Framing.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "hlod/geodesy/EarthCentred.h"

namespace hlod {

double framingDistance(double radius, double fovY, double aspect, double fill) {
  assert(radius > 0.0 && fovY > 0.0 && fovY < 180.0 && aspect > 0.0 && fill > 0.0);
  const double half = std::tan(glm::radians(fovY) * 0.5) * std::min(1.0, aspect) * fill;
  return radius * std::sqrt(1.0 + 1.0 / (half * half));
}

UpFrame modelUpFrame(UpAxis up, const Aabb& bounds) {
  return isEarthCentred(bounds) ? enuUpFrame(bounds.centre()) : upFrame(up);
}

UpFrame modelUpFrame(const Skeleton& skeleton) {
  Aabb roots;
  for (std::uint32_t r : skeleton.roots)
    if (r < skeleton.nodes.size()) roots.extend(skeleton.nodes[r].bounds);
  return modelUpFrame(skeleton.up, roots);
}

glm::dvec3 orbitDirection(const UpFrame& f, double azimuth, double elevation) {
  return std::cos(elevation) * (std::cos(azimuth) * f.first + std::sin(azimuth) * f.second) +
         std::sin(elevation) * f.up;
}

glm::dvec3 defaultViewDirection(const UpFrame& f) {
  const double elevation = glm::radians(30.0);
  // For z up (and east-north-up) the horizontal axes are X, Y: 235 degrees is south-west, a
  // little more from the south. For y up they are Z, X: 30 degrees is the front, a little from
  // the right.
  const bool zUp = f.earthCentred || f.up == glm::dvec3(0.0, 0.0, 1.0);
  return orbitDirection(f, glm::radians(zUp ? 235.0 : 30.0), elevation);
}

Camera frameBounds(const Aabb& bounds, const UpFrame& f, const glm::dvec3& direction, double fovY,
                   double aspect) {
  Camera cam;
  cam.target = bounds.empty() ? glm::dvec3(0.0) : bounds.centre();
  const double radius = std::max(0.5 * glm::length(bounds.size()), 1e-6);
  const double distance = framingDistance(radius, fovY, aspect);
  cam.position = cam.target + glm::normalize(direction) * distance;
  cam.up = f.up;
  cam.fovY = fovY;
  cam.aspect = aspect;
  cam.nearPlane = std::max(distance - radius, distance * 1e-3) * 0.5;
  cam.farPlane = (distance + radius) * 2.0;
  return cam;
}

Camera defaultView(const Aabb& bounds, UpAxis up, double fovY, double aspect) {
  const UpFrame f = modelUpFrame(up, bounds);
  return frameBounds(bounds, f, defaultViewDirection(f), fovY, aspect);
}

}  // namespace hlod
