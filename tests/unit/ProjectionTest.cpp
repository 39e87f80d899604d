// The inverse projections that anchor blocks of projected city models: RD New against its
// published centre and the forward formulas, UTM against the meridian arc integrated here
// (independent of the Krueger series) and against its forward formulas everywhere in a zone.
#include <gtest/gtest.h>

#include <cmath>

#include "hlod/geodesy/Projection.h"

using namespace hlod;

namespace {

constexpr double kRadPerDeg = 0.017453292519943295;

// Metres between two geodetic positions close together (the chord through ECEF).
double groundMetres(const LatLon& a, const LatLon& b) {
  return glm::length(geodeticToEcef(a) - geodeticToEcef(b));
}

// The WGS 84 meridian arc from the equator to `lat` degrees, by Simpson's rule on the radius
// of curvature in the meridian, M = a (1 - e^2) / (1 - e^2 sin^2)^1.5.
double meridianArc(double lat) {
  const int n = 20000;
  const double h = lat * kRadPerDeg / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double s = std::sin(i * h);
    const double m = kWgs84A * (1.0 - kWgs84E2) / std::pow(1.0 - kWgs84E2 * s * s, 1.5);
    sum += m * (i == 0 || i == n ? 1.0 : (i % 2 ? 4.0 : 2.0));
  }
  return sum * h / 3.0;
}

}  // namespace

TEST(RdNew, AmersfoortIsThePublishedCentre) {
  const LatLon p = rdNewToWgs84({155000.0, 463000.0});
  EXPECT_NEAR(p.lat, 52.15517440, 1e-9);
  EXPECT_NEAR(p.lon, 5.38720621, 1e-9);
  const glm::dvec2 back = wgs84ToRdNew({52.15517440, 5.38720621, 0.0});
  EXPECT_NEAR(back.x, 155000.0, 1e-6);
  EXPECT_NEAR(back.y, 463000.0, 1e-6);
}

TEST(RdNew, ForwardAndInverseFormulasAgreeWithinAMetreOverTheNetherlands) {
  for (double x = 20000.0; x <= 280000.0; x += 20000.0)
    for (double y = 310000.0; y <= 620000.0; y += 20000.0) {
      const glm::dvec2 back = wgs84ToRdNew(rdNewToWgs84({x, y}));
      EXPECT_LT(glm::length(back - glm::dvec2(x, y)), 1.0) << x << ", " << y;
    }
}

TEST(RdNew, RotterdamLiesAtFiftyTwoNorthFourAndAHalfEast) {
  // Rotterdam centre, RD about (92500, 437500).
  const LatLon p = rdNewToWgs84({92500.0, 437500.0});
  EXPECT_NEAR(p.lat, 51.92, 0.02);
  EXPECT_NEAR(p.lon, 4.48, 0.02);
  // A kilometre north in RD is a kilometre north on the ground (grid north is near true north).
  const LatLon q = rdNewToWgs84({92500.0, 438500.0});
  EXPECT_NEAR(groundMetres(p, q), 1000.0, 1.0);
}

TEST(Utm, TheCentralMeridianIsTheScaledMeridianArc) {
  for (double lat : {0.0, 10.0, 45.0, 60.0, 80.0}) {
    const double northing = 0.9996 * meridianArc(lat);
    const glm::dvec2 en = wgs84ToUtm({31, true}, {lat, 3.0, 0.0});
    EXPECT_NEAR(en.x, 500000.0, 1e-6) << lat;
    EXPECT_NEAR(en.y, northing, 1e-3) << lat;
    const LatLon p = utmToWgs84({31, true}, {500000.0, northing});
    EXPECT_NEAR(p.lat, lat, 1e-9) << lat;
    EXPECT_NEAR(p.lon, 3.0, 1e-9) << lat;
  }
  // 45 N: the published WGS 84 meridian arc, 4,984,944.378 m.
  EXPECT_NEAR(meridianArc(45.0), 4984944.378, 0.01);
}

TEST(Utm, InverseAndForwardRoundTripToAMillimetreAcrossAZone) {
  for (const UtmZone zone : {UtmZone{31, true}, UtmZone{10, true}, UtmZone{56, false}}) {
    const double lon0 = zone.zone * 6.0 - 183.0;
    for (double dLon = -3.0; dLon <= 3.0; dLon += 0.75)
      for (double lat = 0.5; lat <= 80.0; lat += 9.5) {
        const LatLon p{zone.north ? lat : -lat, lon0 + dLon, 0.0};
        const LatLon back = utmToWgs84(zone, wgs84ToUtm(zone, p));
        EXPECT_LT(groundMetres(p, back), 1e-3) << zone.zone << " " << p.lat << " " << p.lon;
      }
  }
}

TEST(Utm, SouthernZonesCountNorthingFromTenThousandKilometres) {
  const glm::dvec2 en = wgs84ToUtm({56, false}, {-33.8568, 151.2153, 0.0});  // Sydney
  EXPECT_GT(en.y, 6.2e6);
  EXPECT_LT(en.y, 6.3e6);
  EXPECT_NEAR(en.x, 334000.0, 2000.0);
}

TEST(Projection, EpsgCodesPickTheirProjection) {
  EXPECT_TRUE(hasInverseProjection(7415));
  EXPECT_TRUE(hasInverseProjection(28992));
  EXPECT_EQ(utmZoneOf(32631)->zone, 31);
  EXPECT_TRUE(utmZoneOf(32631)->north);
  EXPECT_FALSE(utmZoneOf(32756)->north);
  EXPECT_EQ(utmZoneOf(25832)->zone, 32);
  EXPECT_FALSE(hasInverseProjection(3857));
  EXPECT_FALSE(projectedToWgs84(2056, {2600000.0, 1200000.0, 400.0}).has_value());
  const auto rd = projectedToWgs84(7415, {155000.0, 463000.0, 12.5});
  ASSERT_TRUE(rd);
  EXPECT_NEAR(rd->lat, 52.15517440, 1e-9);
  EXPECT_EQ(rd->height, 12.5);
}
