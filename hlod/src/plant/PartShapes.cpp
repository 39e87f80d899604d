// The power plant's shapes (plant/PartShapes.h).
#include "plant/PartShapes.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace hlod::plant {

namespace {

// v turned by the rotation that takes unit vector from to unit vector to (Rodrigues; the
// smallest such rotation). Opposite vectors: a half turn about an axis perpendicular to both.
dvec3 carry(const dvec3& v, const dvec3& from, const dvec3& to) {
  const dvec3 axis = glm::cross(from, to);
  const double s = glm::length(axis), c = glm::dot(from, to);
  if (s < 1e-12)
    return c > 0.0 ? v : 2.0 * glm::dot(v, perpendicular(from)) * perpendicular(from) - v;
  const dvec3 k = axis / s;
  return v * c + glm::cross(k, v) * s + k * glm::dot(k, v) * (1.0 - c);
}

// The unit vector of angle t in the frame (u, v).
dvec3 around(const dvec3& u, const dvec3& v, double t) {
  return u * std::cos(t) + v * std::sin(t);
}

}  // namespace

double Straight::length() const {
  return glm::length(b - a);
}

dvec3 perpendicular(const dvec3& d) {
  const dvec3 helper = std::abs(d.y) < 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
  return glm::normalize(glm::cross(helper, d));
}

Sweep sweepPolyline(const std::vector<dvec3>& points, double bendRadius, double step,
                    int bendRings) {
  assert(points.size() >= 2 && step > 0.0 && bendRings >= 1);
  Sweep out;
  const std::size_t n = points.size();
  // Per interior point: where its bend starts and ends along the straights.
  std::vector<double> cut(n, 0.0);  // the tangent length taken off both sides
  std::vector<dvec3> dirs(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) dirs[i] = glm::normalize(points[i + 1] - points[i]);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double turn = std::acos(std::clamp(glm::dot(dirs[i - 1], dirs[i]), -1.0, 1.0));
    if (turn < 1e-9) continue;
    const double room = 0.45 * std::min(glm::length(points[i] - points[i - 1]),
                                        glm::length(points[i + 1] - points[i]));
    cut[i] = std::min(bendRadius * std::tan(turn / 2.0), room);
  }
  dvec3 u = perpendicular(dirs[0]);
  dvec3 dir = dirs[0];
  const auto push = [&](const dvec3& c, const dvec3& d) {
    u = glm::normalize(carry(u, dir, d));
    u = glm::normalize(u - d * glm::dot(u, d));
    dir = d;
    if (!out.rings.empty() && glm::length(out.rings.back().centre - c) < 1e-9) return;
    out.rings.push_back({c, d, u});
  };
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const dvec3 d = dirs[i];
    const dvec3 a = points[i] + d * cut[i], b = points[i + 1] - d * cut[i + 1];
    const double len = glm::length(b - a);
    push(a, d);
    const int steps = std::max(1, int(std::ceil(len / step)));
    for (int k = 1; k <= steps; ++k) push(a + (b - a) * (double(k) / steps), d);
    out.straights.push_back({a, b, d, u});
    if (i + 2 >= n || cut[i + 1] <= 0.0) continue;
    // The bend at points[i + 1]: an arc from b (direction d) to the next straight's start.
    const dvec3 next = dirs[i + 1];
    const double turn = std::acos(std::clamp(glm::dot(d, next), -1.0, 1.0));
    const double radius = cut[i + 1] / std::tan(turn / 2.0);
    const dvec3 inward = glm::normalize(next - d * glm::dot(d, next));
    const dvec3 centre = b + inward * radius;
    const int rings = std::max(2, int(std::ceil(bendRings * turn / (M_PI / 2.0))));
    for (int k = 1; k <= rings; ++k) {
      const double t = turn * k / rings;
      const dvec3 p = centre - inward * radius * std::cos(t) + d * radius * std::sin(t);
      push(p, glm::normalize(d * std::cos(t) + inward * std::sin(t)));
    }
  }
  return out;
}

std::uint32_t ShapeBuilder::vertex(const dvec3& p, const dvec3& n) {
  m_.positions.emplace_back(p);
  m_.normals.emplace_back(glm::normalize(n));
  return std::uint32_t(m_.positions.size() - 1);
}

void ShapeBuilder::triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  m_.indices.insert(m_.indices.end(), {a, b, c});
}

void ShapeBuilder::box(const dvec3& lo, const dvec3& hi, const dvec3& o, const dvec3& ex,
                       const dvec3& ey, const dvec3& ez) {
  const auto at = [&](double x, double y, double z) { return o + ex * x + ey * y + ez * z; };
  // Each face: its normal axis (0..2), its side, and corners counter-clockwise seen from outside.
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      dvec3 corner[4];
      const double level = side ? hi[axis] : lo[axis];
      // (a1, a2) counter-clockwise about +axis; reversed for the face facing -axis.
      const double s1[4] = {lo[a1], hi[a1], hi[a1], lo[a1]};
      const double s2[4] = {lo[a2], lo[a2], hi[a2], hi[a2]};
      for (int k = 0; k < 4; ++k) {
        const int j = side ? k : 3 - k;
        dvec3 local(0.0);
        local[axis] = level;
        local[a1] = s1[j];
        local[a2] = s2[j];
        corner[k] = at(local.x, local.y, local.z);
      }
      dvec3 normal(0.0);
      normal[axis] = side ? 1.0 : -1.0;
      const dvec3 n = ex * normal.x + ey * normal.y + ez * normal.z;
      std::uint32_t v[4];
      for (int k = 0; k < 4; ++k) v[k] = vertex(corner[k], n);
      triangle(v[0], v[1], v[2]);
      triangle(v[0], v[2], v[3]);
    }
}

void ShapeBuilder::iBeam(double h, double w, double tf, double tw) {
  box({0.0, -h / 2, -w / 2}, {1.0, -h / 2 + tf, w / 2});
  box({0.0, h / 2 - tf, -w / 2}, {1.0, h / 2, w / 2});
  box({0.0, -h / 2 + tf, -tw / 2}, {1.0, h / 2 - tf, tw / 2});
}

void ShapeBuilder::tube(const std::vector<Ring>& rings, double r, int seg, bool capStart,
                        bool capEnd) {
  tube(rings, std::vector<double>(rings.size(), r), seg, capStart, capEnd);
}

void ShapeBuilder::tube(const std::vector<Ring>& rings, const std::vector<double>& radii, int seg,
                        bool capStart, bool capEnd) {
  assert(rings.size() >= 2 && radii.size() == rings.size() && seg >= 3);
  std::vector<std::uint32_t> first(rings.size());
  for (std::size_t i = 0; i < rings.size(); ++i) {
    const Ring& g = rings[i];
    const dvec3 v = glm::cross(g.dir, g.u);
    // The slope of the radius along the tube tilts the normals (a frustum's side).
    const std::size_t j0 = i == 0 ? 0 : i - 1, j1 = i + 1 < rings.size() ? i + 1 : i;
    const double along = glm::length(rings[j1].centre - rings[j0].centre);
    const double slope = along > 0.0 ? (radii[j0] - radii[j1]) / along : 0.0;
    first[i] = std::uint32_t(m_.positions.size());
    for (int k = 0; k < seg; ++k) {
      const dvec3 e = around(g.u, v, 2.0 * M_PI * k / seg);
      vertex(g.centre + e * radii[i], e + g.dir * slope);
    }
  }
  for (std::size_t i = 0; i + 1 < rings.size(); ++i)
    for (int k = 0; k < seg; ++k) {
      const std::uint32_t a = first[i] + std::uint32_t(k),
                          b = first[i] + std::uint32_t((k + 1) % seg);
      const std::uint32_t c = first[i + 1] + std::uint32_t((k + 1) % seg),
                          d = first[i + 1] + std::uint32_t(k);
      triangle(a, b, c);
      triangle(a, c, d);
    }
  if (capStart) disc(rings.front().centre, -rings.front().dir, rings.front().u, radii.front(), seg);
  if (capEnd) disc(rings.back().centre, rings.back().dir, rings.back().u, radii.back(), seg);
}

void ShapeBuilder::disc(const dvec3& c, const dvec3& n, const dvec3& u, double r, int seg) {
  const dvec3 v = glm::cross(n, u);
  const std::uint32_t centre = vertex(c, n);
  const std::uint32_t first = std::uint32_t(m_.positions.size());
  for (int k = 0; k < seg; ++k) vertex(c + around(u, v, 2.0 * M_PI * k / seg) * r, n);
  for (int k = 0; k < seg; ++k)
    triangle(centre, first + std::uint32_t(k), first + std::uint32_t((k + 1) % seg));
}

void ShapeBuilder::annulus(const dvec3& c, const dvec3& n, const dvec3& u, double r0, double r1,
                           int seg) {
  const dvec3 v = glm::cross(n, u);
  const std::uint32_t first = std::uint32_t(m_.positions.size());
  for (int k = 0; k < seg; ++k) {
    const dvec3 e = around(u, v, 2.0 * M_PI * k / seg);
    vertex(c + e * r0, n);
    vertex(c + e * r1, n);
  }
  for (int k = 0; k < seg; ++k) {
    const std::uint32_t p = first + 2 * std::uint32_t(k),
                        q = first + 2 * std::uint32_t((k + 1) % seg);
    triangle(p, p + 1, q + 1);
    triangle(p, q + 1, q);
  }
}

void ShapeBuilder::cylinder(const dvec3& a, const dvec3& b, double r, int seg) {
  const dvec3 d = glm::normalize(b - a);
  const dvec3 u = perpendicular(d);
  tube({{a, d, u}, {b, d, u}}, r, seg, true, true);
}

void ShapeBuilder::flange(const dvec3& c, const dvec3& d, const dvec3& u, double r, double rf,
                          double halfThickness, int seg) {
  const dvec3 a = c - d * halfThickness, b = c + d * halfThickness;
  tube({{a, d, u}, {b, d, u}}, rf, seg, false, false);
  annulus(a, -d, u, r, rf, seg);
  annulus(b, d, u, r, rf, seg);
}

void ShapeBuilder::dome(const dvec3& c, const dvec3& d, double r, double depth, int seg,
                        int rings) {
  const dvec3 u = perpendicular(d), v = glm::cross(d, u);
  const double s = depth / r;  // the ellipsoid's stretch along d
  std::vector<std::uint32_t> first;
  for (int i = 0; i < rings; ++i) {
    const double phi = 0.5 * M_PI * i / rings;
    first.push_back(std::uint32_t(m_.positions.size()));
    for (int k = 0; k < seg; ++k) {
      const dvec3 e = around(u, v, 2.0 * M_PI * k / seg);
      vertex(c + e * (r * std::cos(phi)) + d * (depth * std::sin(phi)),
             e * std::cos(phi) + d * (std::sin(phi) / s));
    }
  }
  const std::uint32_t pole = vertex(c + d * depth, d);
  for (int i = 0; i < rings; ++i)
    for (int k = 0; k < seg; ++k) {
      const std::uint32_t a = first[std::size_t(i)] + std::uint32_t(k),
                          b = first[std::size_t(i)] + std::uint32_t((k + 1) % seg);
      if (i + 1 == rings) {
        triangle(a, b, pole);
        continue;
      }
      const std::uint32_t cc = first[std::size_t(i) + 1] + std::uint32_t((k + 1) % seg),
                          dd = first[std::size_t(i) + 1] + std::uint32_t(k);
      triangle(a, b, cc);
      triangle(a, cc, dd);
    }
}

void ShapeBuilder::torus(const dvec3& c, const dvec3& axis, double R, double r, int segRing,
                         int segTube) {
  const dvec3 p = perpendicular(axis), q = glm::cross(axis, p);
  std::vector<Ring> rings;
  for (int k = 0; k <= segRing; ++k) {
    const double t = 2.0 * M_PI * k / segRing;
    const dvec3 radial = around(p, q, t);
    rings.push_back({c + radial * R, glm::normalize(around(q, -p, t)), radial});
  }
  tube(rings, r, segTube, false, false);
}

void ShapeBuilder::prism(const dvec3& a, const dvec3& b, double r, int sides) {
  const dvec3 d = glm::normalize(b - a), u = perpendicular(d), v = glm::cross(d, u);
  for (int k = 0; k < sides; ++k) {
    const dvec3 e0 = around(u, v, 2.0 * M_PI * k / sides) * r,
                e1 = around(u, v, 2.0 * M_PI * (k + 1) / sides) * r;
    const dvec3 n = around(u, v, 2.0 * M_PI * (k + 0.5) / sides);
    const std::uint32_t v0 = vertex(a + e0, n), v1 = vertex(a + e1, n), v2 = vertex(b + e1, n),
                        v3 = vertex(b + e0, n);
    triangle(v0, v1, v2);
    triangle(v0, v2, v3);
  }
  disc(a, -d, u, r, sides);
  disc(b, d, u, r, sides);
}

}  // namespace hlod::plant
