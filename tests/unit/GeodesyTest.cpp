// WGS84 geodetic, ECEF and local east-north-up conversions (hlod/geodesy/Geodesy.h): known points,
// published lengths of a degree, and round trips exact to well under a millimetre everywhere,
// the poles and the antimeridian included.
#include "hlod/geodesy/Geodesy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace {

using hlod::EnuFrame;
using hlod::LatLon;

double distance(const glm::dvec3& a, const glm::dvec3& b) {
  return glm::length(a - b);
}

TEST(Geodesy, PointsOnTheAxesAreTheEllipsoidsSemiAxes) {
  const double a = 6378137.0, b = 6356752.314245;  // WGS84, NIMA TR8350.2 table 3.1
  EXPECT_LT(distance(hlod::geodeticToEcef({0, 0, 0}), {a, 0, 0}), 1e-9);
  EXPECT_LT(distance(hlod::geodeticToEcef({0, 90, 0}), {0, a, 0}), 1e-9);
  EXPECT_LT(distance(hlod::geodeticToEcef({0, 180, 0}), {-a, 0, 0}), 1e-9);
  EXPECT_LT(distance(hlod::geodeticToEcef({0, -90, 0}), {0, -a, 0}), 1e-9);
  EXPECT_LT(distance(hlod::geodeticToEcef({90, 0, 0}), {0, 0, b}), 1e-6);
  EXPECT_LT(distance(hlod::geodeticToEcef({-90, 123, 0}), {0, 0, -b}), 1e-6);
  EXPECT_LT(distance(hlod::geodeticToEcef({0, 0, 1000}), {a + 1000, 0, 0}), 1e-9);
  EXPECT_LT(distance(hlod::geodeticToEcef({90, 0, 1000}), {0, 0, b + 1000}), 1e-6);
  // And back: the poles have latitude +-90 and height 0 exactly enough.
  const LatLon north = hlod::ecefToGeodetic({0, 0, b});
  EXPECT_NEAR(north.lat, 90.0, 1e-12);
  EXPECT_NEAR(north.height, 0.0, 1e-6);
  const LatLon east = hlod::ecefToGeodetic({0, a, 0});
  EXPECT_NEAR(east.lat, 0.0, 1e-12);
  EXPECT_NEAR(east.lon, 90.0, 1e-12);
  EXPECT_NEAR(east.height, 0.0, 1e-6);
}

TEST(Geodesy, ADegreeIsAsLongAsPublished) {
  // Published WGS84 lengths of one degree (e.g. the NGA/NIMA tables): of latitude 110,574 m at
  // the equator and 111,694 m at the poles; of longitude 111,319 m at the equator. Measured over
  // a thousandth of a degree, where the chord is the arc to a micrometre.
  const EnuFrame equator(LatLon{0, 0, 0});
  const glm::dvec3 north = equator.fromGeodetic({0.001, 0, 0});
  EXPECT_NEAR(north.y * 1000.0, 110574.0, 1.0);
  EXPECT_NEAR(north.x, 0.0, 1e-9);
  const glm::dvec3 east = equator.fromGeodetic({0, 0.001, 0});
  EXPECT_NEAR(east.x * 1000.0, 111319.5, 1.0);
  EXPECT_NEAR(east.y, 0.0, 1e-9);
  const EnuFrame nearPole(LatLon{89.9995, 0, 0});
  const glm::dvec3 towardsPole = nearPole.fromGeodetic({89.9995 + 0.0005, 0, 0});
  EXPECT_NEAR(towardsPole.y * 2000.0, 111694.0, 1.0);
  EXPECT_NEAR(towardsPole.x, 0.0, 1e-9);
}

TEST(Geodesy, GeodeticRoundTripsAreExactToAMicrometreEverywhere) {
  const std::vector<double> lats = {-90.0, -89.9999999, -60.5, -1e-9, 0.0, 37.87, 89.9999, 90.0};
  const std::vector<double> lons = {-180.0, -179.9999999, -122.27, 0.0, 45.5, 179.9999999, 180.0};
  const std::vector<double> heights = {-11000.0, 0.0, 8848.0, 1e5, 3.6e7};
  double worst = 0.0;
  for (double lat : lats)
    for (double lon : lons)
      for (double h : heights) {
        const glm::dvec3 e = hlod::geodeticToEcef({lat, lon, h});
        const LatLon back = hlod::ecefToGeodetic(e);
        ASSERT_TRUE(std::isfinite(back.lat) && std::isfinite(back.lon) &&
                    std::isfinite(back.height));
        EXPECT_GE(back.lat, -90.0);
        EXPECT_LE(back.lat, 90.0);
        EXPECT_GT(back.lon, -180.0 - 1e-12);
        EXPECT_LE(back.lon, 180.0);
        EXPECT_NEAR(back.height, h, 1e-6) << lat << " " << lon << " " << h;
        // Compared in metres: at a pole the longitude is any, and it wraps at +-180.
        worst = std::max(worst, distance(hlod::geodeticToEcef(back), e));
      }
  EXPECT_LT(worst, 1e-6);
}

TEST(Geodesy, EcefRoundTripsAreExactToAMicrometre) {
  // A deterministic spread of points from 5,000 km to 50,000 km from the centre.
  double worst = 0.0;
  std::uint64_t state = 12345;
  auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 dir = glm::normalize(glm::dvec3(next() - 0.5, next() - 0.5, next() - 0.5));
    const glm::dvec3 p = dir * (5e6 + 4.5e7 * next() * next());
    worst = std::max(worst, distance(hlod::geodeticToEcef(hlod::ecefToGeodetic(p)), p));
  }
  EXPECT_LT(worst, 1e-6);
  // The centre of the earth is finite.
  const LatLon centre = hlod::ecefToGeodetic({0, 0, 0});
  EXPECT_TRUE(std::isfinite(centre.lat) && std::isfinite(centre.lon) &&
              std::isfinite(centre.height));
}

TEST(Geodesy, AnEnuFrameIsOrthonormalEastNorthUpAtItsOrigin) {
  for (const LatLon o : {LatLon{37.87, -122.27, 50.0}, LatLon{90, 0, 0}, LatLon{-90, 45, 0},
                         LatLon{0, 180, 0}, LatLon{-33.9, 18.4, 1000}}) {
    const EnuFrame f(o);
    const glm::dmat3 r = f.rotation();
    const glm::dmat3 identity = r * glm::transpose(r);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(identity[c][k], c == k ? 1.0 : 0.0, 1e-15);
    EXPECT_NEAR(glm::determinant(r), 1.0, 1e-15);  // right-handed
    // The origin is 0, a point straight above it is up, and round trips hold.
    EXPECT_LT(glm::length(f.fromGeodetic(o)), 1e-9);
    const glm::dvec3 above = f.fromGeodetic({o.lat, o.lon, o.height + 100.0});
    EXPECT_LT(distance(above, {0, 0, 100}), 1e-8);
    const glm::dvec3 p{1234.5, -678.9, 12.3};
    EXPECT_LT(distance(f.fromEcef(f.toEcef(p)), p), 1e-9);
    const LatLon g = f.toGeodetic(p);
    EXPECT_LT(distance(f.fromGeodetic(g), p), 1e-6);
  }
}

TEST(Geodesy, EnuToEnuIsTheSameAsGoingThroughEcef) {
  const EnuFrame a(LatLon{10.0, 179.9995, 3.0}), b(LatLon{10.0005, -179.999, -2.0});
  const hlod::EnuToEnu ab(a, b);
  for (const glm::dvec3 p : {glm::dvec3(0.0), glm::dvec3(100, -50, 20), glm::dvec3(-3e3, 2e3, 1)}) {
    EXPECT_LT(distance(ab.point(p), b.fromEcef(a.toEcef(p))), 1e-8);
  }
  // A rigid motion: lengths are kept.
  EXPECT_NEAR(glm::length(ab.direction({3, 4, 12})), 13.0, 1e-12);
}

}  // namespace
