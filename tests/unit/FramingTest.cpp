// Framing: a still view fills the frame with the model's box (its corners projected through the
// camera's own basis), centred; the orbit around the store's up axis (a y-up store's circles y
// with +y up) keeps the projected bounding sphere within the frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

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

struct Projected {
  double xMin = 1e300, xMax = -1e300, yMin = 1e300, yMax = -1e300;  // [-1, 1]: the frame's edges
  double hullShare = 0.0;  // the convex hull of the corners, as a share of the frame
};

// The box's corners projected through the camera's own basis (not through frameBounds' maths).
Projected projectCorners(const Camera& cam, const Aabb& box) {
  const double tanY = std::tan(glm::radians(cam.fovY) * 0.5), tanX = tanY * cam.aspect;
  const glm::dvec3 f = cam.forward(), r = cam.right(), u = cam.trueUp();
  Projected out;
  std::vector<glm::dvec2> points;
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 p(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                       i & 4 ? box.max.z : box.min.z);
    const glm::dvec3 v = p - cam.position;
    const double depth = glm::dot(v, f);
    EXPECT_GT(depth, 0.0) << "a corner behind the camera";
    const glm::dvec2 q(glm::dot(v, r) / depth / tanX, glm::dot(v, u) / depth / tanY);
    out.xMin = std::min(out.xMin, q.x), out.xMax = std::max(out.xMax, q.x);
    out.yMin = std::min(out.yMin, q.y), out.yMax = std::max(out.yMax, q.y);
    points.push_back(q);
  }
  // Andrew's monotone chain, then the shoelace formula; the frame is 2 x 2.
  std::sort(points.begin(), points.end(),
            [](const auto& a, const auto& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  auto cross = [](glm::dvec2 o, glm::dvec2 a, glm::dvec2 b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  std::vector<glm::dvec2> hull;
  for (int pass = 0; pass < 2; ++pass) {
    const std::size_t start = hull.size();
    for (const glm::dvec2& p : points) {
      while (hull.size() >= start + 2 && cross(hull[hull.size() - 2], hull.back(), p) <= 0.0)
        hull.pop_back();
      hull.push_back(p);
    }
    hull.pop_back();
    std::reverse(points.begin(), points.end());
  }
  double area = 0.0;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const glm::dvec2 a = hull[i], b = hull[(i + 1) % hull.size()];
    area += a.x * b.y - b.x * a.y;
  }
  out.hullShare = std::abs(area) * 0.5 / 4.0;
  return out;
}

Aabb boxOf(glm::dvec3 lo, glm::dvec3 hi) {
  Aabb b;
  b.extend(lo);
  b.extend(hi);
  return b;
}

// The old framing, for comparison: the bounding sphere at kFramingFill of the smaller side.
Camera sphereFramed(const Aabb& box, UpAxis up, double fov, double aspect) {
  Camera cam;
  cam.target = box.centre();
  cam.position = cam.target + defaultViewDirection(up) *
                                  framingDistance(0.5 * glm::length(box.size()), fov, aspect);
  cam.up = upVector(up);
  cam.fovY = fov;
  cam.aspect = aspect;
  return cam;
}

}  // namespace

TEST(Framing, TheFramedBoxReachesTheFrameOnOneAxisCentredOnBoth) {
  // Hand-made boxes: a cube, a flat city district, a long thin row, a tower; standing on z or on
  // y; in landscape, portrait and square frames; narrow to wide lenses.
  const std::vector<Aabb> boxes = {
      boxOf({0, 0, 0}, {10, 10, 10}), boxOf({-500, 200, 0}, {500, 1200, 30}),
      boxOf({0, 0, 0}, {1000, 20, 10}), boxOf({0, 0, 0}, {10, 10, 300}),
      boxOf({6.3e6, 1e3, -50}, {6.3e6 + 600, 1.3e3, 10})};  // far from the origin
  for (UpAxis up : {UpAxis::Z, UpAxis::Y}) {
    for (const Aabb& box : boxes) {
      for (const auto& [w, h] : {std::pair{1280, 720}, std::pair{720, 1280}, std::pair{512, 512}}) {
        for (double fov : {30.0, 50.0, 90.0}) {
          SCOPED_TRACE(std::string(upAxisName(up)) + "-up, box size " +
                       std::to_string(box.size().x) + " x " + std::to_string(box.size().y) + " x " +
                       std::to_string(box.size().z) + ", " + std::to_string(w) + "x" +
                       std::to_string(h) + ", fov " + std::to_string(fov));
          const double aspect = double(w) / h;
          const Camera cam = frameBounds(box, up, defaultViewDirection(up), fov, aspect);
          const Projected p = projectCorners(cam, box);
          // Inside the filled part of the frame, reaching it on one axis.
          EXPECT_GE(p.xMin, -kBoxFramingFill - 1e-9);
          EXPECT_LE(p.xMax, kBoxFramingFill + 1e-9);
          EXPECT_GE(p.yMin, -kBoxFramingFill - 1e-9);
          EXPECT_LE(p.yMax, kBoxFramingFill + 1e-9);
          EXPECT_NEAR(std::max(p.xMax, p.yMax), kBoxFramingFill, 1e-6);
          // Centred on both axes.
          EXPECT_NEAR(p.xMin + p.xMax, 0.0, 1e-6);
          EXPECT_NEAR(p.yMin + p.yMax, 0.0, 1e-6);
          // The box between near and far, the camera upright.
          EXPECT_EQ(cam.up, upVector(up));
          EXPECT_LT(cam.nearPlane, glm::length(cam.target - cam.position));
        }
      }
    }
  }
}

TEST(Framing, AFlatDistrictSeenFromAboveFillsMostOfALandscapeFrame) {
  // 1 km x 1 km, 30 m tall (a district of CityJSON buildings) in a 16:9 frame, 50 degree lens:
  // seen diagonally from 30 degrees above its outline is a flattened diamond, which can cover
  // at most half of its bounding rectangle; framed by its box it spans the frame's width and
  // covers 40% of it, three times what its bounding sphere gave.
  const Aabb district = boxOf({0, 0, 0}, {1000, 1000, 30});
  const double aspect = 16.0 / 9.0;
  const Projected boxFramed = projectCorners(
      frameBounds(district, UpAxis::Z, defaultViewDirection(UpAxis::Z), 50.0, aspect), district);
  const Projected sphere =
      projectCorners(sphereFramed(district, UpAxis::Z, 50.0, aspect), district);
  EXPECT_GT(boxFramed.hullShare, 0.40);
  EXPECT_GT(boxFramed.hullShare, 3.0 * sphere.hullShare);
  EXPECT_NEAR(boxFramed.xMax - boxFramed.xMin, 2.0 * kBoxFramingFill, 1e-6);  // the width
  // A cube in a square frame covers more than half of it.
  const Aabb cube = boxOf({0, 0, 0}, {10, 10, 10});
  EXPECT_GT(
      projectCorners(frameBounds(cube, UpAxis::Y, defaultViewDirection(UpAxis::Y), 50.0, 1.0), cube)
          .hullShare,
      0.55);
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
