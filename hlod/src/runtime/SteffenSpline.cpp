// Steffen's monotone cubic Hermite interpolation of camera keyframes (runtime/SteffenSpline.h).
#include "runtime/SteffenSpline.h"

#include <algorithm>
#include <cmath>

#include "runtime/Finite.h"

namespace hlod {

namespace {

// A field whose last keyframe repeats its first, up to rounding (an orbit's angle 2 pi), is a
// loop: its ends get the tangent of an interior keyframe between the last and the first
// interval, so that the loop is C1 across the seam as everywhere else.
bool isLoop(const std::vector<CameraKeyframe>& k, glm::dvec3 CameraKeyframe::*field) {
  if (k.size() < 3) return false;
  double extent = 0.0;
  for (const CameraKeyframe& key : k) {
    extent = std::max(extent, glm::length(key.*field - k.front().*field));
  }
  return extent > 0.0 && glm::length(k.back().*field - k.front().*field) <= 1e-9 * extent;
}

}  // namespace

// Steffen's tangent at an interior keyframe from the slopes dl (over an interval hl) on its left
// and dr (over hr) on its right: the slope of the parabola through the three keyframes, limited
// to twice the smaller slope, and 0 at a turn or beside a flat interval. Tangents of the slope's
// sign and at most twice it at both ends of an interval keep the cubic monotone there, so it
// stays between its two keyframe values (Steffen 1990).
double steffenInterior(double dl, double dr, double hl, double hr) {
  if (dl == 0.0 || dr == 0.0 || (dl > 0.0) != (dr > 0.0)) return 0.0;
  const double w = hl / (hl + hr);
  const double parabola = dl * (1.0 - w) + dr * w;
  return std::copysign(2.0 * std::min({std::abs(dl), std::abs(dr), 0.5 * std::abs(parabola)}), dr);
}

// Steffen's tangent at an end keyframe, slope d0 over h0 next to it and d1 over h1 after that:
// the end slope of the parabola through the three end keyframes, limited in the same way
// (Steffen 1990). The same formula serves both ends (it is odd in the slopes).
double steffenEnd(double d0, double d1, double h0, double h1) {
  const double w = h0 / (h0 + h1);
  const double parabola = d0 * (1.0 + w) - d1 * w;
  if (d0 == 0.0 || parabola == 0.0 || (parabola > 0.0) != (d0 > 0.0)) return 0.0;
  return std::abs(parabola) > 2.0 * std::abs(d0) ? 2.0 * d0 : parabola;
}

std::vector<glm::dvec3> monotoneTangents(const std::vector<CameraKeyframe>& k,
                                         glm::dvec3 CameraKeyframe::*field) {
  const std::size_t n = k.size();
  std::vector<double> h(n - 1);
  std::vector<glm::dvec3> d(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    h[i] = k[i + 1].time - k[i].time;
    d[i] = (k[i + 1].*field - k[i].*field) / h[i];
  }
  std::vector<glm::dvec3> m(n);
  if (n == 2) {
    m[0] = m[1] = d[0];  // a straight line
    return m;
  }
  const bool loop = isLoop(k, field);
  for (int c = 0; c < 3; ++c) {
    for (std::size_t i = 1; i + 1 < n; ++i) {
      m[i][c] = steffenInterior(d[i - 1][c], d[i][c], h[i - 1], h[i]);
    }
    if (loop) {
      m[0][c] = m[n - 1][c] = steffenInterior(d[n - 2][c], d[0][c], h[n - 2], h[0]);
    } else {
      m[0][c] = steffenEnd(d[0][c], d[1][c], h[0], h[1]);
      m[n - 1][c] = steffenEnd(d[n - 2][c], d[n - 3][c], h[n - 2], h[n - 3]);
    }
  }
  return m;
}

bool slopesFinite(const std::vector<CameraKeyframe>& k, glm::dvec3 CameraKeyframe::*field) {
  for (std::size_t i = 0; i + 1 < k.size(); ++i) {
    const glm::dvec3 change = k[i + 1].*field - k[i].*field;
    if (!finite(4.0 * change) || !finite(4.0 * change / (k[i + 1].time - k[i].time))) {
      return false;
    }
  }
  return true;
}

glm::dvec3 hermite(const glm::dvec3& p0, const glm::dvec3& m0, const glm::dvec3& p1,
                   const glm::dvec3& m1, double h, double s) {
  const double s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * h * m0 + (-2 * s3 + 3 * s2) * p1 +
         (s3 - s2) * h * m1;
}

glm::dvec3 hermiteDerivative(const glm::dvec3& p0, const glm::dvec3& m0, const glm::dvec3& p1,
                             const glm::dvec3& m1, double h, double s) {
  const double s2 = s * s;
  return ((6 * s2 - 6 * s) * p0 + (3 * s2 - 4 * s + 1) * h * m0 + (-6 * s2 + 6 * s) * p1 +
          (3 * s2 - 2 * s) * h * m1) /
         h;
}

}  // namespace hlod
