#include "hlod/runtime/Framing.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace hlod {

double framingDistance(double radius, double fovY, double aspect, double fill) {
  assert(radius > 0.0 && fovY > 0.0 && fovY < 180.0 && aspect > 0.0 && fill > 0.0);
  const double half = std::tan(glm::radians(fovY) * 0.5) * std::min(1.0, aspect) * fill;
  return radius * std::sqrt(1.0 + 1.0 / (half * half));
}

glm::dvec3 orbitDirection(UpAxis up, double azimuth, double elevation) {
  glm::dvec3 first, second;
  horizontalAxes(up, first, second);
  return std::cos(elevation) * (std::cos(azimuth) * first + std::sin(azimuth) * second) +
         std::sin(elevation) * upVector(up);
}

glm::dvec3 defaultViewDirection(UpAxis up) {
  const double elevation = glm::radians(30.0);
  // For z up the horizontal axes are X, Y: 235 degrees is south-west, a little more from the
  // south. For y up they are Z, X: 30 degrees is the front, a little from the right.
  return orbitDirection(up, glm::radians(up == UpAxis::Z ? 235.0 : 30.0), elevation);
}

Camera frameBounds(const Aabb& bounds, UpAxis up, const glm::dvec3& direction, double fovY,
                   double aspect) {
  Camera cam;
  cam.target = bounds.empty() ? glm::dvec3(0.0) : bounds.centre();
  const double radius = std::max(0.5 * glm::length(bounds.size()), 1e-6);
  const double distance = framingDistance(radius, fovY, aspect);
  cam.position = cam.target + glm::normalize(direction) * distance;
  cam.up = upVector(up);
  cam.fovY = fovY;
  cam.aspect = aspect;
  cam.nearPlane = std::max(distance - radius, distance * 1e-3) * 0.5;
  cam.farPlane = (distance + radius) * 2.0;
  return cam;
}

}  // namespace hlod
