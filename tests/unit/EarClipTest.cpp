// earClip on hard polygons: every simple polygon of n points and h holes gives n - 2 + 2h
// triangles, their area sums to the polygon's, and none lies outside it.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hlod/import/EarClip.h"

namespace hlod {
namespace {

using Rings = std::vector<std::vector<glm::dvec3>>;

std::vector<glm::dvec3> ring2d(std::initializer_list<std::pair<double, double>> pts) {
  std::vector<glm::dvec3> r;
  for (auto [x, y] : pts) r.emplace_back(x, y, 0.0);
  return r;
}

double shoelace(const std::vector<glm::dvec3>& r) {
  double a = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const auto &p = r[i], &q = r[(i + 1) % r.size()];
    a += p.x * q.y - q.x * p.y;
  }
  return 0.5 * a;
}

double polygonArea(const Rings& rings) {
  double a = std::abs(shoelace(rings[0]));
  for (std::size_t h = 1; h < rings.size(); ++h) a -= std::abs(shoelace(rings[h]));
  return a;
}

bool insideRing(const std::vector<glm::dvec3>& r, const glm::dvec2& q) {
  bool in = false;
  for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++)
    if ((r[i].y > q.y) != (r[j].y > q.y) &&
        q.x < (r[j].x - r[i].x) * (q.y - r[i].y) / (r[j].y - r[i].y) + r[i].x)
      in = !in;
  return in;
}

std::vector<glm::dvec3> flat(const Rings& rings) {
  std::vector<glm::dvec3> all;
  for (const auto& r : rings) all.insert(all.end(), r.begin(), r.end());
  return all;
}

// The checks every triangulation of a planar (z = 0) polygon must pass.
void expectTriangulates(const Rings& rings, std::size_t expectedTriangles) {
  const EarClipResult r = earClip(rings);
  EXPECT_EQ(r.status, EarClipStatus::Ok);
  EXPECT_EQ(r.droppedHoles, 0u);
  ASSERT_EQ(r.triangles.size(), expectedTriangles);
  const auto pts = flat(rings);
  const double sign = shoelace(rings[0]) > 0 ? 1.0 : -1.0;
  double area = 0.0;
  for (const auto& t : r.triangles) {
    for (auto i : t) ASSERT_LT(i, pts.size());
    const glm::dvec3 &a = pts[t[0]], &b = pts[t[1]], &c = pts[t[2]];
    const double signedArea = 0.5 * glm::cross(b - a, c - a).z * sign;
    EXPECT_GT(signedArea, 0.0) << "wound as the outer ring";
    area += signedArea;
    const glm::dvec3 centroid = (a + b + c) / 3.0;
    const glm::dvec2 q(centroid.x, centroid.y);
    bool inside = insideRing(rings[0], q);
    for (std::size_t h = 1; h < rings.size(); ++h) inside = inside && !insideRing(rings[h], q);
    EXPECT_TRUE(inside) << "triangle centroid (" << q.x << ", " << q.y << ") outside the polygon";
  }
  EXPECT_NEAR(area, polygonArea(rings), 1e-9 * polygonArea(rings));
}

Rings comb() {
  return {ring2d({{0, 0}, {9, 0}, {9, 5}, {8, 5}, {8, 1}, {7, 1}, {7, 5}, {6, 5}, {6, 1}, {5, 1},
                  {5, 5}, {4, 5}, {4, 1}, {3, 1}, {3, 5}, {2, 5}, {2, 1}, {1, 1}, {1, 5}, {0, 5}})};
}

TEST(EarClip, ACombGivesNMinusTwoTrianglesInsideIt) {
  expectTriangulates(comb(), 18);
  EXPECT_DOUBLE_EQ(polygonArea(comb()), 29.0);
}

TEST(EarClip, AClockwiseRingIsTriangulatedAndKeepsItsWinding) {
  Rings r = comb();
  std::reverse(r[0].begin(), r[0].end());
  expectTriangulates(r, 18);
}

TEST(EarClip, ASpiralTwoTurnsLongIsTriangulated) {
  // Between the curves r = 1 + t and r = 1.8 + t, t = theta / pi, over two turns.
  std::vector<glm::dvec3> ring;
  const int steps = 96;
  for (int i = 0; i <= steps; ++i) {
    const double th = 4.0 * std::numbers::pi * i / steps, r = 1.8 + th / std::numbers::pi;
    ring.emplace_back(r * std::cos(th), r * std::sin(th), 0.0);
  }
  for (int i = steps; i >= 0; --i) {
    const double th = 4.0 * std::numbers::pi * i / steps, r = 1.0 + th / std::numbers::pi;
    ring.emplace_back(r * std::cos(th), r * std::sin(th), 0.0);
  }
  expectTriangulates({ring}, ring.size() - 2);
}

TEST(EarClip, ASquareWithTwoHolesBridgesBoth) {
  // The holes are given counter-clockwise, as the outer ring: earClip orients them itself.
  const Rings r = {ring2d({{0, 0}, {10, 0}, {10, 10}, {0, 10}}),
                   ring2d({{2, 2}, {4, 2}, {4, 4}, {2, 4}}),
                   ring2d({{6, 5}, {8, 5}, {8, 8}, {6, 8}})};
  expectTriangulates(r, 12 - 2 + 2 * 2);
  EXPECT_DOUBLE_EQ(polygonArea(r), 90.0);
}

TEST(EarClip, HolesOnTheSameRayAsEachOtherAreBridged) {
  // Both holes' rightmost vertices at y = 5: the second bridge must see past the first.
  const Rings r = {ring2d({{0, 0}, {20, 0}, {20, 10}, {0, 10}}), ring2d({{2, 4}, {5, 5}, {2, 6}}),
                   ring2d({{9, 4}, {12, 5}, {9, 6}}), ring2d({{14, 3}, {16, 3}, {16, 7}, {14, 7}})};
  expectTriangulates(r, 14 - 2 + 2 * 3);
}

TEST(EarClip, CollinearRunsUseEveryPointWithoutZeroAreaTriangles) {
  const Rings r = {ring2d({{0, 0},
                           {1, 0},
                           {2, 0},
                           {3, 0},
                           {3, 1},
                           {3, 2},
                           {3, 3},
                           {2, 3},
                           {1, 3},
                           {0, 3},
                           {0, 2},
                           {0, 1}})};
  expectTriangulates(r, 10);
}

TEST(EarClip, DuplicateConsecutivePointsAndTheClosingRepeatAreIgnored) {
  const Rings r = {
      ring2d({{0, 0}, {0, 0}, {4, 0}, {4, 0}, {4, 0}, {4, 3}, {2, 5}, {2, 5}, {0, 3}, {0, 0}})};
  const EarClipResult res = earClip(r);
  EXPECT_EQ(res.status, EarClipStatus::Ok);
  EXPECT_EQ(res.triangles.size(), 5u - 2u);  // five distinct points
  double area = 0.0;
  for (const auto& t : res.triangles)
    area += 0.5 * glm::cross(r[0][t[1]] - r[0][t[0]], r[0][t[2]] - r[0][t[0]]).z;
  EXPECT_NEAR(area, 4 * 3 + 0.5 * 4 * 2, 1e-12);
}

TEST(EarClip, ANearDegenerateSliverIsStillTriangulated) {
  expectTriangulates({ring2d({{0, 0}, {100, 0}, {100, 1e-6}, {0, 1e-6}})}, 2);
  expectTriangulates({ring2d({{0, 0}, {1, 0}, {0.5, 1e-9}})}, 1);
}

TEST(EarClip, RingsWithoutAreaAreDegenerateNotErrors) {
  EXPECT_EQ(earClip({ring2d({{0, 0}, {1, 1}, {2, 2}, {3, 3}})}).status, EarClipStatus::Degenerate);
  EXPECT_EQ(earClip({ring2d({{1, 1}, {1, 1}, {1, 1}})}).status, EarClipStatus::Degenerate);
  EXPECT_EQ(earClip({ring2d({{0, 0}, {1, 0}})}).status, EarClipStatus::Degenerate);
  EXPECT_EQ(earClip({}).status, EarClipStatus::Degenerate);
}

TEST(EarClip, AHoleWithoutAreaIsDroppedAndCounted) {
  const EarClipResult r =
      earClip({ring2d({{0, 0}, {4, 0}, {4, 4}, {0, 4}}), ring2d({{1, 1}, {2, 2}, {3, 3}})});
  EXPECT_EQ(r.status, EarClipStatus::Ok);
  EXPECT_EQ(r.droppedHoles, 1u);
  EXPECT_EQ(r.triangles.size(), 2u);
}

TEST(EarClip, ATiltedFacadeFarFromTheOriginKeepsItsAreaAndNormal) {
  // A 10 x 6 wall with a 2 x 2 window, in a vertical plane facing (1, 1, 0), at RD/UTM-like
  // coordinates of a few million metres.
  const glm::dvec3 o(4424648.79, 5482614.69, 310.19);
  const glm::dvec3 along = glm::normalize(glm::dvec3(-1, 1, 0)), up(0, 0, 1);
  auto at = [&](double s, double t) { return o + along * s + up * t; };
  const Rings r = {{at(0, 0), at(10, 0), at(10, 6), at(0, 6)},
                   {at(4, 2), at(4, 4), at(6, 4), at(6, 2)}};
  const EarClipResult res = earClip(r);
  ASSERT_EQ(res.status, EarClipStatus::Ok);
  ASSERT_EQ(res.triangles.size(), 8u);
  const auto pts = flat(r);
  const glm::dvec3 facing = glm::normalize(glm::cross(along, up));
  double area = 0.0;
  for (const auto& t : res.triangles) {
    const glm::dvec3 n = 0.5 * glm::cross(pts[t[1]] - pts[t[0]], pts[t[2]] - pts[t[0]]);
    EXPECT_GT(glm::dot(n, facing), 0.0);
    area += glm::length(n);
  }
  EXPECT_NEAR(area, 56.0, 1e-6);
}

}  // namespace
}  // namespace hlod
