#include "hlod/runtime/Camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hlod {

namespace {

Plane makePlane(const glm::dvec3& normal, const glm::dvec3& point) {
  const glm::dvec3 n = glm::normalize(normal);
  return Plane{n, -glm::dot(n, point)};
}

}  // namespace

glm::dvec3 Camera::forward() const {
  const glm::dvec3 f = target - position;
  const double len = glm::length(f);
  if (!(len > 0.0) || !std::isfinite(len)) return {0.0, 1.0, 0.0};
  return f / len;
}

glm::dvec3 Camera::right() const {
  const glm::dvec3 f = forward();
  glm::dvec3 r = glm::cross(f, up);
  double len = glm::length(r);
  if (!(len > 1e-12)) {
    // up parallel to the view direction: pick any perpendicular axis.
    r = glm::cross(f, std::abs(f.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0));
    len = glm::length(r);
  }
  return r / len;
}

glm::dvec3 Camera::trueUp() const {
  return glm::cross(right(), forward());
}

Frustum Camera::frustum() const {
  const glm::dvec3 f = forward();
  const glm::dvec3 r = right();
  const glm::dvec3 u = trueUp();
  const double halfV = std::tan(glm::radians(std::clamp(fovY, 1e-3, 179.0)) * 0.5);
  const double halfH = halfV * (aspect > 0.0 ? aspect : 1.0);
  Frustum fr;
  // Side planes pass through the eye; their inward normals are perpendicular to the edge rays.
  fr.planes[0] = makePlane(f * halfH + r, position);  // left:  normal leans right
  fr.planes[1] = makePlane(f * halfH - r, position);  // right
  fr.planes[2] = makePlane(f * halfV + u, position);  // bottom
  fr.planes[3] = makePlane(f * halfV - u, position);  // top
  fr.planes[4] = makePlane(f, position + f * nearPlane);
  fr.planes[5] = makePlane(-f, position + f * farPlane);
  return fr;
}

double Frustum::distanceOutside(const Aabb& box) const {
  if (box.empty()) return 0.0;
  double outside = 0.0;
  for (const Plane& p : planes) {
    // The box corner furthest along the inward normal: if even it is behind the plane, the whole
    // box is outside by at least that much.
    const glm::dvec3 corner{p.normal.x >= 0.0 ? box.max.x : box.min.x,
                            p.normal.y >= 0.0 ? box.max.y : box.min.y,
                            p.normal.z >= 0.0 ? box.max.z : box.min.z};
    outside = std::max(outside, -p.signedDistance(corner));
  }
  return outside;
}

double Camera::pixelsPerUnit(double distance, double viewportHeight) const {
  const double halfV = std::tan(glm::radians(std::clamp(fovY, 1e-3, 179.0)) * 0.5);
  return viewportHeight / (2.0 * halfV * std::max(distance, 1e-9));
}

double projectedPixels(const View& view, const Aabb& box) {
  const double d = distanceToBox(view.camera.position, box);
  if (!(d > 0.0)) return std::numeric_limits<double>::infinity();
  return glm::length(box.size()) * view.camera.pixelsPerUnit(d, view.viewportHeight);
}

double distanceToBox(const glm::dvec3& p, const Aabb& box) {
  if (box.empty()) return glm::length(p);
  const glm::dvec3 q = glm::clamp(p, box.min, box.max);
  return glm::length(p - q);
}

}  // namespace hlod
