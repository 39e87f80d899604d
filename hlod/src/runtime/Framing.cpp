#include "hlod/runtime/Framing.h"

#include <algorithm>
#include <array>
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

namespace {

std::array<glm::dvec3, 8> corners(const Aabb& b) {
  std::array<glm::dvec3, 8> c;
  for (int i = 0; i < 8; ++i)
    c[std::size_t(i)] = {i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y,
                         i & 4 ? b.max.z : b.min.z};
  return c;
}

}  // namespace

Camera frameBounds(const Aabb& bounds, const UpFrame& frame, const glm::dvec3& direction,
                   double fovY, double aspect) {
  assert(fovY > 0.0 && fovY < 180.0 && aspect > 0.0);
  Camera cam;
  cam.up = frame.up;
  cam.fovY = fovY;
  cam.aspect = aspect;
  const Aabb box = bounds.empty() ? Aabb{glm::dvec3(0.0), glm::dvec3(0.0)} : bounds;
  const double size = std::max(glm::length(box.size()), 1e-6);
  // The image plane's basis depends on the direction alone (Camera's own, degenerate up too).
  cam.target = glm::dvec3(0.0);
  cam.position = glm::normalize(direction);
  const glm::dvec3 f = cam.forward(), r = cam.right(), u = cam.trueUp();
  const double tanY = std::tan(glm::radians(fovY) * 0.5) * kBoxFramingFill;
  const double tanX = tanY * aspect;
  const std::array<glm::dvec3, 8> points = corners(box);

  // The camera at a r + b u + g f sees corner p inside the filled frame when
  // |p.r - a| <= tanX (p.f - g) and |p.u - b| <= tanY (p.f - g): linear in (a, b, g). Nearest
  // (largest g) for one axis: the two families of bounds on g, one rising and one falling with
  // the offset, meet at the offset that centres the projection on that axis.
  auto nearest = [&](const glm::dvec3& axis, double tanA) {
    double rising = 1e300, falling = 1e300;
    for (const glm::dvec3& p : points) {
      rising = std::min(rising, glm::dot(p, f) - glm::dot(p, axis) / tanA);
      falling = std::min(falling, glm::dot(p, f) + glm::dot(p, axis) / tanA);
    }
    return std::pair{tanA * 0.5 * (falling - rising), 0.5 * (rising + falling)};
  };
  auto [a, gX] = nearest(r, tanX);
  auto [b, gY] = nearest(u, tanY);
  double nearestDepth = 1e300;
  for (const glm::dvec3& p : points) nearestDepth = std::min(nearestDepth, glm::dot(p, f));
  // The axis the box reaches first decides; every corner stays ahead of the camera.
  const double g = std::min({gX, gY, nearestDepth - 1e-3 * size});
  // On the other axis (room to spare at g) the offset that centres the projection: the sum of its
  // extremes falls as the offset grows, so bisection finds it.
  auto centred = [&](const glm::dvec3& axis) {
    double lo = 1e300, hi = -1e300;
    for (const glm::dvec3& p : points) {
      lo = std::min(lo, glm::dot(p, axis));
      hi = std::max(hi, glm::dot(p, axis));
    }
    for (int i = 0; i < 100; ++i) {
      const double s = 0.5 * (lo + hi);
      double most = -1e300, least = 1e300;
      for (const glm::dvec3& p : points) {
        const double q = (glm::dot(p, axis) - s) / (glm::dot(p, f) - g);
        most = std::max(most, q), least = std::min(least, q);
      }
      (most + least > 0.0 ? lo : hi) = s;
    }
    return 0.5 * (lo + hi);
  };
  if (gX > g) a = centred(r);
  if (gY > g) b = centred(u);
  cam.position = a * r + b * u + g * f;
  const double distance = glm::dot(box.centre() - cam.position, f);
  cam.target = cam.position + f * distance;
  double nearestCorner = 1e300, farthestCorner = 0.0;
  for (const glm::dvec3& p : points) {
    const double depth = glm::dot(p - cam.position, f);
    nearestCorner = std::min(nearestCorner, depth);
    farthestCorner = std::max(farthestCorner, depth);
  }
  cam.nearPlane = std::max(nearestCorner, distance * 1e-3) * 0.5;
  cam.farPlane = std::max(farthestCorner, distance) * 2.0;
  return cam;
}

Camera defaultView(const Aabb& bounds, UpAxis up, double fovY, double aspect) {
  const UpFrame f = modelUpFrame(up, bounds);
  return frameBounds(bounds, f, defaultViewDirection(f), fovY, aspect);
}

}  // namespace hlod
