// Geocentric data without hand-made cameras (hlod/geodesy/EarthCentred.h, modelUpFrame): a
// model lying on the earth in ECEF stands on its ellipsoid normal for the default view and the
// orbit, and the street paths refuse it with a message that suggests the orbit.
#include <gtest/gtest.h>

#include <cmath>

#include "hlod/geodesy/EarthCentred.h"
#include "hlod/geodesy/Geodesy.h"
#include "hlod/runtime/CameraPath.h"
#include "hlod/runtime/Framing.h"

using namespace hlod;

namespace {

// One node: a 2 km x 2 km patch of ground at (lat, lon), 50 m thick, in ECEF.
Skeleton ecefSkeleton(double lat, double lon, UpAxis up) {
  Skeleton s;
  s.up = up;
  NodeInfo n;
  const EnuFrame enu(LatLon{lat, lon, 300.0});
  for (double x : {-1000.0, 1000.0})
    for (double y : {-1000.0, 1000.0})
      for (double z : {0.0, 50.0}) n.bounds.extend(enu.toEcef({x, y, z}));
  n.centre = n.bounds.centre();
  s.nodes.push_back(n);
  s.roots.push_back(0);
  return s;
}

glm::dvec3 normalAt(double lat, double lon) {
  const double a = glm::radians(lat), b = glm::radians(lon);
  return {std::cos(a) * std::cos(b), std::cos(a) * std::sin(b), std::sin(a)};
}

TEST(EarthCentred, APatchOfGroundInEcefIsEarthCentredAndALocalModelIsNot) {
  const Skeleton sk = ecefSkeleton(47.4, 8.5, UpAxis::Y);
  EXPECT_TRUE(isEarthCentred(sk.nodes[0].bounds));
  Aabb local;
  local.extend(glm::dvec3(-500, -500, 0));
  local.extend(glm::dvec3(500, 500, 80));
  EXPECT_FALSE(isEarthCentred(local));
  // Far from the origin but not on the earth: a point 6,500 km out is, one at 20,000 km is not.
  EXPECT_TRUE(isEarthCentred(glm::dvec3(6.5e6, 0, 0)));
  EXPECT_FALSE(isEarthCentred(glm::dvec3(2.0e7, 0, 0)));
}

TEST(EarthCentred, TheModelsUpIsTheEllipsoidNormalAtItsCentre) {
  for (const auto& [lat, lon] :
       {std::pair{47.4, 8.5}, {-33.9, 151.2}, {0.0, -90.0}, {78.2, 15.6}}) {
    const Skeleton sk = ecefSkeleton(lat, lon, UpAxis::Y);
    const UpFrame f = modelUpFrame(sk);
    EXPECT_TRUE(f.earthCentred);
    // The geodetic normal at the centre (the patch spans 0.02 degrees: within 2e-4).
    EXPECT_GT(glm::dot(f.up, normalAt(lat, lon)), 1.0 - 1e-7) << lat << " " << lon;
    EXPECT_NEAR(glm::dot(f.first, f.second), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(glm::cross(f.first, f.second), f.up), 1.0, 1e-12);
  }
  // A local model keeps its axis.
  Skeleton local;
  local.up = UpAxis::Y;
  NodeInfo n;
  n.bounds.extend(glm::dvec3(-1.0));
  n.bounds.extend(glm::dvec3(1.0));
  local.nodes.push_back(n);
  local.roots.push_back(0);
  EXPECT_EQ(modelUpFrame(local).up, glm::dvec3(0, 1, 0));
}

TEST(EarthCentred, TheDefaultViewAndTheOrbitLookDownOnTheGroundFrom30DegreesAbove) {
  const Skeleton sk = ecefSkeleton(47.4, 8.5, UpAxis::Y);
  const glm::dvec3 up = normalAt(47.4, 8.5);
  const Camera cam = defaultView(sk.nodes[0].bounds, sk.up, 60.0, 16.0 / 9.0);
  const glm::dvec3 toCamera = glm::normalize(cam.position - cam.target);
  EXPECT_NEAR(glm::dot(toCamera, up), 0.5, 1e-3);  // 30 degrees above the local horizon
  EXPECT_GT(glm::dot(cam.up, up), 1.0 - 1e-6);
  auto path = makeOrbitPath(sk, 10.0);
  ASSERT_TRUE(path) << path.message();
  const auto samples = path->sampleAt(2.0);
  ASSERT_FALSE(samples.empty());
  for (const auto& s : samples) {
    // Every frame looks down at the patch's centre from 30 degrees above its horizon: before,
    // the orbit turned about y, sideways on the globe, and most frames showed sky.
    const glm::dvec3 d = glm::normalize(s.camera.position - s.camera.target);
    EXPECT_NEAR(glm::dot(d, up), 0.5, 1e-3);
    EXPECT_GT(glm::dot(s.camera.up, up), 1.0 - 1e-6);
  }
}

TEST(EarthCentred, StreetPathsRefuseEarthCentredStoresAndSuggestTheOrbit) {
  const Skeleton sk = ecefSkeleton(47.4, 8.5, UpAxis::Z);
  auto walk = makeWalkFlyPath(sk);
  ASSERT_FALSE(walk);
  EXPECT_NE(walk.message().find("earth-centred"), std::string::npos) << walk.message();
  EXPECT_NE(walk.message().find("--kind orbit"), std::string::npos) << walk.message();
  EXPECT_FALSE(makeDrivePath(sk));
}

}  // namespace
