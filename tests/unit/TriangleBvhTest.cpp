#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "hlod/metrics/TriangleBvh.h"

namespace hlod::metrics {
namespace {

// Triangles scattered over a 100-unit cube at `at`, sizes from a hundredth to ten units; every
// seventh has collinear corners and every eleventh a repeated one.
std::vector<Triangle> scatter(std::size_t n, const glm::dvec3& at, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Triangle> out;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 a = at + 100.0 * glm::dvec3(u(rng), u(rng), u(rng));
    const double size = std::pow(10.0, -2.0 + 3.0 * u(rng));
    const glm::dvec3 e1 = size * glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
    const glm::dvec3 e2 = size * glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
    if (i % 7 == 0)
      out.push_back({a, a + e1, a + 2.0 * e1});
    else if (i % 11 == 0)
      out.push_back({a, a, a + e2});
    else
      out.push_back({a, a + e1, a + e2});
  }
  return out;
}

// Each triangle's own squared distance to p, through a tree of that triangle alone (one leaf,
// no box to hide it): the exact figure the tree compares.
struct Brute {
  explicit Brute(const std::vector<Triangle>& tris) {
    for (const Triangle& t : tris) singles.emplace_back(std::vector<Triangle>{t});
  }
  double distance2(std::size_t i, const glm::dvec3& p) const { return singles[i].distance2(p); }
  double closest2(const glm::dvec3& p) const {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < singles.size(); ++i) best = std::min(best, distance2(i, p));
    return best;
  }
  std::vector<TriangleBvh> singles;
};

// The tree's float boxes must never hide the closest triangle, near the origin or 6,000 km from
// it (where a float's step is half a metre): every answer equals the one of trying them all.
class TriangleBvhExact : public testing::TestWithParam<double> {};

TEST_P(TriangleBvhExact, AnswersEqualThoseOfTryingEveryTriangle) {
  const glm::dvec3 at(GetParam(), -0.5 * GetParam(), 0.25 * GetParam());
  const std::vector<Triangle> tris = scatter(3000, at, 5);
  const TriangleBvh bvh(tris);
  const Brute brute(tris);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-10.0, 110.0);
  std::uint32_t hint = TriangleBvh::kNoHint;
  std::uint32_t nearHint = TriangleBvh::kNoHint;
  std::vector<std::uint32_t> near;
  for (int k = 0; k < 400; ++k) {
    // Half the points on a triangle (distance about 0), half anywhere around the cloud.
    const Triangle& t = tris[std::size_t(k) * 7 % tris.size()];
    const glm::dvec3 p =
        k % 2 ? (t[0] + t[1] + t[2]) / 3.0 : at + glm::dvec3(u(rng), u(rng), u(rng));
    const double want2 = brute.closest2(p);
    double closest2 = -1.0;
    // The last query's closest triangle first: near this point or anywhere.
    bvh.nearest(p, 1e-3, near, &closest2, &nearHint);
    EXPECT_EQ(near, bvh.nearest(p, 1e-3));
    EXPECT_EQ(bvh.distance2(p), want2);
    EXPECT_EQ(closest2, want2);
    EXPECT_EQ(bvh.distance(p), std::sqrt(want2));
    double wantDistance = std::numeric_limits<double>::infinity();
    for (const Triangle& each : tris)
      wantDistance = std::min(wantDistance, pointTriangleDistance(p, each));
    EXPECT_EQ(bvh.distance(p), wantDistance);
    std::vector<std::uint32_t> wantNear;
    const double limit = std::sqrt(want2) + 1e-3;
    for (std::uint32_t i = 0; i < tris.size(); ++i)
      if (brute.distance2(i, p) <= limit * limit) wantNear.push_back(i);
    EXPECT_EQ(near, wantNear);
    for (double r2 : {0.5 * want2, want2, 2.0 * want2 + 1e-9}) {
      const bool want = want2 <= r2;
      EXPECT_EQ(bvh.within2(p, r2, hint), want) << "r2 " << r2 << " want2 " << want2;
      const double r = std::sqrt(r2);
      EXPECT_EQ(bvh.within(p, r), want2 <= r * r);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(NearAndFarFromTheOrigin, TriangleBvhExact, testing::Values(0.0, 6.0e6));

TEST(TriangleBvh, AHintThatNamesNoTriangleWithinTheRadiusChangesNoAnswer) {
  const std::vector<Triangle> tris = scatter(500, glm::dvec3(0.0), 3);
  const TriangleBvh bvh(tris);
  const glm::dvec3 p = (tris[10][0] + tris[10][1] + tris[10][2]) / 3.0;
  std::uint32_t hint = TriangleBvh::kNoHint;
  ASSERT_TRUE(bvh.within2(p, 1e-12, hint));
  ASSERT_NE(hint, TriangleBvh::kNoHint);
  // The same hint far from that triangle: the search goes on and finds what is there.
  const glm::dvec3 far = (tris[200][0] + tris[200][1] + tris[200][2]) / 3.0;
  std::uint32_t stale = hint;
  EXPECT_TRUE(bvh.within2(far, 1e-12, stale));
  EXPECT_NE(stale, hint);
  stale = hint;
  EXPECT_FALSE(bvh.within2(glm::dvec3(-1000.0), 1.0, stale));
}

TEST(TriangleBvh, OneTriangleOrManyAtOnePointAreTrees) {
  const glm::dvec3 a(1, 2, 3);
  const TriangleBvh one({Triangle{a, a + glm::dvec3(1, 0, 0), a + glm::dvec3(0, 1, 0)}});
  EXPECT_DOUBLE_EQ(one.distance(a + glm::dvec3(0, 0, 2)), 2.0);
  const TriangleBvh points(std::vector<Triangle>(40, Triangle{a, a, a}));
  EXPECT_DOUBLE_EQ(points.distance(a + glm::dvec3(3, 4, 0)), 5.0);
  EXPECT_EQ(points.nearest(a, 0.0).size(), 40u);
}

}  // namespace
}  // namespace hlod::metrics

namespace hlod::metrics {
namespace {

// Möller-Trumbore against every triangle (the same arithmetic), the nearest t: what firstHit
// must find.
TriangleBvh::Hit bruteHit(const std::vector<Triangle>& tris, const glm::dvec3& o,
                          const glm::dvec3& d, double tMax, bool frontOnly) {
  TriangleBvh::Hit best;
  double bestT = tMax;
  for (std::uint32_t i = 0; i < tris.size(); ++i) {
    const Triangle& tri = tris[i];
    const glm::dvec3 e1 = tri[1] - tri[0], e2 = tri[2] - tri[0];
    const glm::dvec3 n = glm::cross(e1, e2);
    if (glm::dot(n, n) <= 1e-24 * glm::dot(e1, e1) * glm::dot(e2, e2)) continue;  // no area
    const glm::dvec3 pv = glm::cross(d, e2);
    const double det = glm::dot(e1, pv);
    if (det == 0.0 || (frontOnly && det < 0.0)) continue;
    const glm::dvec3 tv = o - tri[0];
    const double u = glm::dot(tv, pv) / det;
    const glm::dvec3 qv = glm::cross(tv, e1);
    const double v = glm::dot(d, qv) / det;
    const double t = glm::dot(e2, qv) / det;
    if (u < 0.0 || u > 1.0 || v < 0.0 || u + v > 1.0 || t < 0.0 || t > bestT) continue;
    bestT = t;
    best = {i, t, u, v};
  }
  return best;
}

TEST(TriangleBvh, FirstHitIsTheNearestTriangleOnTheSegmentAsTryingEach) {
  const std::vector<Triangle> tris = scatter(3000, glm::dvec3(-50.0), 11);
  const TriangleBvh bvh(tris);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0;
  for (int i = 0; i < 300; ++i) {
    // Aimed at a triangle's centroid, or anywhere: mostly hits, some misses.
    const glm::dvec3 o = 60.0 * glm::dvec3(u(rng), u(rng), u(rng));
    const Triangle& aim =
        tris[std::size_t((u(rng) + 1.0) * 0.5 * double(tris.size())) % tris.size()];
    const glm::dvec3 d = i % 4 == 0 ? glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)))
                                    : glm::normalize((aim[0] + aim[1] + aim[2]) / 3.0 - o);
    for (const bool front : {false, true}) {
      const auto want = bruteHit(tris, o, d, 300.0, front);
      const auto got = bvh.firstHit(o, d, 300.0, front);
      ASSERT_EQ(bool(got), bool(want)) << i;
      if (!want) continue;
      ++hits;
      // The same triangle, or one met at the same distance up to rounding (1/det vs / det).
      EXPECT_NEAR(got.t, want.t, 1e-9 * (1.0 + want.t)) << i;
      if (got.triangle != want.triangle) {
        EXPECT_NEAR(got.t, want.t, 1e-9) << i;
      }
    }
  }
  EXPECT_GT(hits, 200);
}

TEST(TriangleBvh, FirstHitGivesTheBarycentricPointAndSkipsBackFacesWhenAsked) {
  // One triangle in z = 0, front (counter-clockwise) facing +z.
  const TriangleBvh bvh({Triangle{glm::dvec3(0, 0, 0), glm::dvec3(4, 0, 0), glm::dvec3(0, 4, 0)}});
  const auto down = bvh.firstHit({1.0, 2.0, 10.0}, {0.0, 0.0, -1.0}, 20.0, true);
  ASSERT_TRUE(down);
  EXPECT_DOUBLE_EQ(down.t, 10.0);
  EXPECT_DOUBLE_EQ(down.u, 0.25);  // weight of (4, 0, 0)
  EXPECT_DOUBLE_EQ(down.v, 0.5);   // weight of (0, 4, 0)
  EXPECT_FALSE(bvh.firstHit({1.0, 2.0, -10.0}, {0.0, 0.0, 1.0}, 20.0, true));
  EXPECT_TRUE(bvh.firstHit({1.0, 2.0, -10.0}, {0.0, 0.0, 1.0}, 20.0, false));
  EXPECT_FALSE(bvh.firstHit({1.0, 2.0, 10.0}, {0.0, 0.0, -1.0}, 9.0));   // ends short of it
  EXPECT_FALSE(bvh.firstHit({5.0, 5.0, 10.0}, {0.0, 0.0, -1.0}, 20.0));  // beside it
}

}  // namespace
}  // namespace hlod::metrics
