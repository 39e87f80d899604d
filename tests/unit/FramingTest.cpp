// Framing and the orbit around the store's up axis: a y-up store's orbit circles y with +y up,
// and the projected bounding sphere fills most of the frame's smaller side.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "RuntimeTestScene.h"
#include "hlod/runtime/CameraPath.h"
#include "hlod/runtime/Framing.h"

using namespace hlod;

namespace {

// A one-node skeleton standing on `up`: a tall box (as a y-up truck or engine).
Skeleton boxSkeleton(UpAxis up) {
  Skeleton s;
  s.up = up;
  NodeInfo n;
  n.bounds.extend(glm::dvec3(-1.0, -2.0, -0.5));
  n.bounds.extend(glm::dvec3(3.0, 4.0, 1.5));
  s.nodes.push_back(n);
  s.roots.push_back(0);
  return s;
}

// The share of the frame's smaller side the sphere's outline spans, measured by projecting
// points of the sphere through the camera's own basis (not through framingDistance).
double projectedFill(const Camera& cam, const glm::dvec3& centre, double radius, int width,
                     int height) {
  const double tanY = std::tan(glm::radians(cam.fovY) * 0.5), tanX = tanY * cam.aspect;
  const glm::dvec3 f = cam.forward(), r = cam.right(), u = cam.trueUp();
  double xMin = 1e300, xMax = -1e300, yMin = 1e300, yMax = -1e300;
  const int n = 4000;  // a Fibonacci sphere
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, ring = std::sqrt(1.0 - z * z);
    const double a = i * 2.399963229728653;
    const glm::dvec3 p = centre + radius * glm::dvec3(ring * std::cos(a), ring * std::sin(a), z);
    const glm::dvec3 v = p - cam.position;
    const double depth = glm::dot(v, f);
    EXPECT_GT(depth, 0.0) << "the sphere reaches behind the camera";
    const double x = glm::dot(v, r) / depth / tanX * 0.5 * width;  // pixels from the centre
    const double y = glm::dot(v, u) / depth / tanY * 0.5 * height;
    xMin = std::min(xMin, x), xMax = std::max(xMax, x);
    yMin = std::min(yMin, y), yMax = std::max(yMax, y);
  }
  return std::max(xMax - xMin, yMax - yMin) / std::min(width, height);
}

}  // namespace

TEST(Framing, TheFramedSphereFillsMostOfTheSmallerSideInLandscapeAndPortrait) {
  for (const auto& [w, h] : {std::pair{1280, 720}, std::pair{720, 1280}, std::pair{512, 512}}) {
    for (double fov : {30.0, 50.0, 60.0, 90.0}) {
      Aabb box;
      box.extend(glm::dvec3(10.0, 20.0, 30.0));
      box.extend(glm::dvec3(14.0, 23.0, 40.0));
      const double aspect = double(w) / h;
      const Camera cam = frameBounds(box, UpAxis::Y, defaultViewDirection(UpAxis::Y), fov, aspect);
      const double fill = projectedFill(cam, box.centre(), 0.5 * glm::length(box.size()), w, h);
      EXPECT_GT(fill, 0.5) << w << "x" << h << " fov " << fov;
      EXPECT_LT(fill, 1.0) << w << "x" << h << " fov " << fov;
      EXPECT_NEAR(fill, kFramingFill, 0.01) << w << "x" << h << " fov " << fov;
      EXPECT_EQ(cam.up, glm::dvec3(0.0, 1.0, 0.0));
    }
  }
}

TEST(Framing, DefaultViewsLookDownOnTheModelFromItsUpSide) {
  for (UpAxis up : {UpAxis::X, UpAxis::Y, UpAxis::Z}) {
    const glm::dvec3 d = defaultViewDirection(up);
    EXPECT_NEAR(glm::length(d), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(d, upVector(up)), 0.5, 1e-12) << upAxisName(up);  // 30 degrees above
  }
  EXPECT_GT(defaultViewDirection(UpAxis::Y).z, 0.5);  // a y-up model is seen from its front
}

TEST(OrbitPath, AYUpStoreIsCircledAroundYWithYUp) {
  const Skeleton sk = boxSkeleton(UpAxis::Y);
  auto path = makeCameraPath("orbit", sk);
  ASSERT_TRUE(path) << path.message();
  const auto& k = path->keyframes();
  ASSERT_GE(k.size(), 25u);
  const glm::dvec3 normal =
      glm::normalize(glm::cross(k[6].position - k[0].position, k[12].position - k[0].position));
  EXPECT_GT(std::abs(normal.y), 1.0 - 1e-9) << normal.x << " " << normal.y << " " << normal.z;
  const glm::dvec3 c = sk.nodes[0].bounds.centre();
  for (const CameraKeyframe& key : k) {
    EXPECT_EQ(key.up, glm::dvec3(0.0, 1.0, 0.0));
    EXPECT_NEAR(key.position.y, k[0].position.y, 1e-9);  // one circle, above the centre
    EXPECT_GT(key.position.y, c.y);
  }
  for (const CameraSample& s : path->sampleAt(4.0, 1280.0 / 720.0)) {
    EXPECT_NEAR(s.camera.up.y, 1.0, 1e-9);
    const double fill =
        projectedFill(s.camera, c, 0.5 * glm::length(sk.nodes[0].bounds.size()), 1280, 720);
    EXPECT_GT(fill, 0.5) << "t=" << s.time;
    EXPECT_LT(fill, 1.0) << "t=" << s.time;
  }
}

TEST(OrbitPath, AZUpCityIsStillCircledAroundZ) {
  const Skeleton sk = test::makeSyntheticCity({});
  auto path = makeOrbitPath(sk);
  ASSERT_TRUE(path) << path.message();
  for (const CameraKeyframe& key : path->keyframes()) {
    EXPECT_EQ(key.up, glm::dvec3(0.0, 0.0, 1.0));
    EXPECT_NEAR(key.position.z, path->keyframes()[0].position.z, 1e-9);
  }
}

TEST(OrbitPath, CityKindsOnAYUpStoreNameTheKindAndSuggestOrbit) {
  const Skeleton sk = boxSkeleton(UpAxis::Y);
  for (const char* kind : {"walk-fly", "drive"}) {
    auto path = makeCameraPath(kind, sk);
    ASSERT_FALSE(path) << kind;
    EXPECT_NE(path.message().find(kind), std::string::npos) << path.message();
    EXPECT_NE(path.message().find("orbit"), std::string::npos) << path.message();
    EXPECT_NE(path.message().find("y-up"), std::string::npos) << path.message();
  }
}
