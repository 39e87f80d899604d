// WGS84 geodetic <-> ECEF <-> local ENU conversions (see hlod/geodesy/Geodesy.h).
#include "hlod/geodesy/Geodesy.h"

#include <cmath>

namespace hlod {

namespace {

// N, the prime vertical radius of curvature at a latitude with sine s.
double primeVerticalRadius(double s) {
  return kWgs84A / std::sqrt(1.0 - kWgs84E2 * s * s);
}

}  // namespace

glm::dvec3 geodeticToEcef(const LatLon& p) {
  const double lat = p.lat * kRadPerDeg, lon = p.lon * kRadPerDeg;
  const double sLat = std::sin(lat), cLat = std::cos(lat);
  const double n = primeVerticalRadius(sLat);
  return {(n + p.height) * cLat * std::cos(lon), (n + p.height) * cLat * std::sin(lon),
          (n * (1.0 - kWgs84E2) + p.height) * sLat};
}

LatLon ecefToGeodetic(const glm::dvec3& e) {
  const double p = std::hypot(e.x, e.y);
  LatLon out;
  out.lon = p > 0.0 ? std::atan2(e.y, e.x) / kRadPerDeg : 0.0;
  // Fixed-point iteration on tan(lat) = (z + e^2 N sin(lat)) / p, started from the latitude of a
  // point on the ellipsoid. Each step shrinks the error by about e^2 (0.0067) for points outside
  // the inner ~40 km of the earth, so a handful of steps reach the last bit; unlike
  // h = p / cos(lat) - N it stays exact at the poles (p = 0).
  double lat = std::atan2(e.z, p * (1.0 - kWgs84E2));
  for (int i = 0; i < 10; ++i) {
    const double s = std::sin(lat);
    const double next = std::atan2(e.z + kWgs84E2 * primeVerticalRadius(s) * s, p);
    const bool done = std::abs(next - lat) < 1e-15;
    lat = next;
    if (done) break;
  }
  const double s = std::sin(lat), c = std::cos(lat);
  // The distance along the normal, valid at every latitude: p cos + z sin - a^2 / N.
  out.height = p * c + e.z * s - kWgs84A * std::sqrt(1.0 - kWgs84E2 * s * s);
  out.lat = lat / kRadPerDeg;
  return out;
}

EnuFrame::EnuFrame(const LatLon& origin) : origin_(origin), originEcef_(geodeticToEcef(origin)) {
  const double lat = origin.lat * kRadPerDeg, lon = origin.lon * kRadPerDeg;
  const double sLat = std::sin(lat), cLat = std::cos(lat);
  const double sLon = std::sin(lon), cLon = std::cos(lon);
  const glm::dvec3 east{-sLon, cLon, 0.0};
  const glm::dvec3 north{-sLat * cLon, -sLat * sLon, cLat};
  const glm::dvec3 up{cLat * cLon, cLat * sLon, sLat};
  // glm is column-major: row r of the matrix is (m[0][r], m[1][r], m[2][r]).
  for (int c = 0; c < 3; ++c) {
    rotation_[c][0] = east[c];
    rotation_[c][1] = north[c];
    rotation_[c][2] = up[c];
  }
}

glm::dvec3 EnuFrame::fromEcef(const glm::dvec3& ecef) const {
  return rotation_ * (ecef - originEcef_);
}

glm::dvec3 EnuFrame::toEcef(const glm::dvec3& enu) const {
  return originEcef_ + glm::transpose(rotation_) * enu;
}

EnuToEnu::EnuToEnu(const EnuFrame& from, const EnuFrame& to)
    : rotation(to.rotation() * glm::transpose(from.rotation())),
      // The origins' difference first: two numbers of 6.4e6 m whose difference is exact to 1e-9
      // m, so the offset keeps the precision of the nearby frames.
      offset(to.rotation() * (from.originEcef() - to.originEcef())) {}

}  // namespace hlod
