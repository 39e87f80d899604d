// UTM: the transverse Mercator on the WGS 84 ellipsoid by Krueger's series in the third
// flattening n, to n^4 (Karney 2011, eqs. 35-36 with the coefficients of his sec. 2; the n^4
// terms move points by about 0.05 mm, the series error beyond them is smaller still).
#include <algorithm>
#include <cmath>

#include "hlod/geodesy/Projection.h"

namespace hlod {

namespace {

constexpr double kK0 = 0.9996;  // UTM's scale on the central meridian
constexpr double kFalseEasting = 500000.0;
constexpr double kFalseNorthingSouth = 10000000.0;

struct Series {
  double a;  // A: the rectifying radius, 2 pi A is the meridian's length
  double alpha[4], beta[4], delta[4];
};

Series makeSeries() {
  const double n = kWgs84F / (2.0 - kWgs84F), n2 = n * n, n3 = n2 * n, n4 = n3 * n;
  Series s{};
  s.a = kWgs84A / (1.0 + n) * (1.0 + n2 / 4.0 + n4 / 64.0);
  // Conformal latitude and transverse coordinates -> (xi, eta): forward.
  s.alpha[0] = n / 2.0 - 2.0 * n2 / 3.0 + 5.0 * n3 / 16.0 + 41.0 * n4 / 180.0;
  s.alpha[1] = 13.0 * n2 / 48.0 - 3.0 * n3 / 5.0 + 557.0 * n4 / 1440.0;
  s.alpha[2] = 61.0 * n3 / 240.0 - 103.0 * n4 / 140.0;
  s.alpha[3] = 49561.0 * n4 / 161280.0;
  // (xi, eta) -> (xi', eta'): inverse.
  s.beta[0] = n / 2.0 - 2.0 * n2 / 3.0 + 37.0 * n3 / 96.0 - n4 / 360.0;
  s.beta[1] = n2 / 48.0 + n3 / 15.0 - 437.0 * n4 / 1440.0;
  s.beta[2] = 17.0 * n3 / 480.0 - 37.0 * n4 / 840.0;
  s.beta[3] = 4397.0 * n4 / 161280.0;
  // Conformal latitude chi -> geodetic latitude.
  s.delta[0] = 2.0 * n - 2.0 * n2 / 3.0 - 2.0 * n3 + 116.0 * n4 / 45.0;
  s.delta[1] = 7.0 * n2 / 3.0 - 8.0 * n3 / 5.0 - 227.0 * n4 / 45.0;
  s.delta[2] = 56.0 * n3 / 15.0 - 136.0 * n4 / 35.0;
  s.delta[3] = 4279.0 * n4 / 630.0;
  return s;
}

const Series& series() {
  static const Series s = makeSeries();
  return s;
}

double centralMeridian(const UtmZone& zone) {
  return double(zone.zone) * 6.0 - 183.0;
}

}  // namespace

LatLon utmToWgs84(const UtmZone& zone, const glm::dvec2& en) {
  const Series& s = series();
  const double northing = en.y - (zone.north ? 0.0 : kFalseNorthingSouth);
  const double xi = northing / (kK0 * s.a), eta = (en.x - kFalseEasting) / (kK0 * s.a);
  double xiP = xi, etaP = eta;
  for (int j = 1; j <= 4; ++j) {
    xiP -= s.beta[j - 1] * std::sin(2.0 * j * xi) * std::cosh(2.0 * j * eta);
    etaP -= s.beta[j - 1] * std::cos(2.0 * j * xi) * std::sinh(2.0 * j * eta);
  }
  const double chi = std::asin(std::clamp(std::sin(xiP) / std::cosh(etaP), -1.0, 1.0));
  double lat = chi;
  for (int j = 1; j <= 4; ++j) lat += s.delta[j - 1] * std::sin(2.0 * j * chi);
  const double lon =
      centralMeridian(zone) + std::atan2(std::sinh(etaP), std::cos(xiP)) / kRadPerDeg;
  return {lat / kRadPerDeg, lon > 180.0 ? lon - 360.0 : (lon < -180.0 ? lon + 360.0 : lon), 0.0};
}

glm::dvec2 wgs84ToUtm(const UtmZone& zone, const LatLon& p) {
  const Series& s = series();
  const double n = kWgs84F / (2.0 - kWgs84F);
  const double phi = p.lat * kRadPerDeg;
  double dLon = p.lon - centralMeridian(zone);
  dLon -= 360.0 * std::round(dLon / 360.0);
  const double lam = dLon * kRadPerDeg;
  // The conformal latitude, as tan: t = sinh(atanh(sin phi) - e atanh(e sin phi)).
  const double e = 2.0 * std::sqrt(n) / (1.0 + n);
  const double sinPhi = std::sin(phi);
  const double t = std::sinh(std::atanh(sinPhi) - e * std::atanh(e * sinPhi));
  const double xiP = std::atan2(t, std::cos(lam));
  const double etaP = std::atanh(std::sin(lam) / std::sqrt(1.0 + t * t));
  double xi = xiP, eta = etaP;
  for (int j = 1; j <= 4; ++j) {
    xi += s.alpha[j - 1] * std::sin(2.0 * j * xiP) * std::cosh(2.0 * j * etaP);
    eta += s.alpha[j - 1] * std::cos(2.0 * j * xiP) * std::sinh(2.0 * j * etaP);
  }
  return {kFalseEasting + kK0 * s.a * eta,
          (zone.north ? 0.0 : kFalseNorthingSouth) + kK0 * s.a * xi};
}

}  // namespace hlod
