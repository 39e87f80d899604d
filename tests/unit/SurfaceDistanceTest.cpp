#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "MetricsTestInputs.h"

#include "hlod/metrics/SurfaceDistance.h"

namespace hlod::metrics {
namespace {

using test::rippledSquare;
using test::square;

Mesh triangle(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  Mesh m;
  m.positions = {a, b, c};
  m.indices = {0, 1, 2};
  return m;
}

// A tiny triangle around p: its samples all lie within 1e-9 of p.
Mesh speck(glm::dvec3 p) {
  return triangle(p, p + glm::dvec3(1e-9, 0, 0), p + glm::dvec3(0, 1e-9, 1e-9));
}

TEST(SurfaceDistance, ASquareAgainstItselfIsZero) {
  const Result<SurfaceDistance> d = surfaceDistance(square(1), square(5), 20000);
  ASSERT_TRUE(d.ok()) << d.message();
  EXPECT_LT(d->hausdorff, 1e-12);
  EXPECT_LT(d->rms, 1e-12);
  EXPECT_LT(d->meanAB, 1e-12);
  EXPECT_LT(d->meanBA, 1e-12);
  EXPECT_EQ(d->samples, 40000u);
}

TEST(SurfaceDistance, ASquareAgainstItsCopyOffsetAlongTheNormalIsTheOffset) {
  const Result<SurfaceDistance> d = surfaceDistance(square(3), square(7, 0.1), 20000);
  ASSERT_TRUE(d.ok()) << d.message();
  EXPECT_NEAR(d->hausdorff, 0.1, 1e-12);
  EXPECT_NEAR(d->rms, 0.1, 1e-12);
  EXPECT_NEAR(d->meanAB, 0.1, 1e-12);
  EXPECT_NEAR(d->meanBA, 0.1, 1e-12);
}

TEST(SurfaceDistance, ATriangleAgainstASubsetOfItIsTheFarthestCornersDistance) {
  // b is the lower-left quarter of a: every point of b lies on a (distance 0); a's farthest
  // points from b are its corners (1, 0) and (0, 1), 0.5 from b's corners (0.5, 0) and (0, 0.5).
  const Mesh a = triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  const Mesh b = triangle({0, 0, 0}, {0.5, 0, 0}, {0, 0.5, 0});
  const Result<SurfaceDistance> d = surfaceDistance(a, b);
  ASSERT_TRUE(d.ok()) << d.message();
  EXPECT_LT(d->meanBA, 1e-12);
  EXPECT_GT(d->meanAB, 0.05);
  // Sampling reaches within eps of a corner with probability 1 - (1 - eps^2)^n: eps = 0.005
  // at n = 100000 (probability 1 - e^-2.5 per corner, and there are two).
  EXPECT_LE(d->hausdorff, 0.5 + 1e-12);
  EXPECT_GT(d->hausdorff, 0.5 - 0.005);
  EXPECT_EQ(d->samples, 200000u);
}

TEST(SurfaceDistance, DistanceToATriangleIsExactInEveryVoronoiRegion) {
  // One triangle in z = 0 and points off each corner, edge and the face, each a speck.
  const Mesh t = triangle({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  struct Case {
    glm::dvec3 p;
    double expected;
    const char* region;
  };
  const Case cases[] = {
      {{-3, -4, 0}, 5.0, "corner a"}, {{5, -4, 0}, 5.0, "corner b"},
      {{0, 3, 0}, 1.0, "corner c"},   {{1, -2, 0}, 2.0, "edge ab"},
      {{-1, 1, 0}, 1.0, "edge ca"},   {{2, 2, 0}, std::sqrt(2.0), "edge bc"},
      {{0.5, 0.5, 0.7}, 0.7, "face"}, {{0.5, 0.5, -0.3}, 0.3, "face, other side"},
  };
  for (const Case& c : cases) {
    const Result<SurfaceDistance> d = surfaceDistance(speck(c.p), t, 200);
    ASSERT_TRUE(d.ok()) << d.message();
    EXPECT_NEAR(d->meanAB, c.expected, 1e-8) << c.region;
  }
}

TEST(SurfaceDistance, DegenerateTrianglesAreNeverSampledAndCountAsTheirEdges) {
  // b: a unit square plus a collinear triangle along x in [3, 5] and one with a repeated corner.
  Mesh b = square(1);
  const std::uint32_t base = static_cast<std::uint32_t>(b.positions.size());
  b.positions.insert(b.positions.end(), {{3, 0, 0}, {4, 0, 0}, {5, 0, 0}, {8, 8, 8}, {9, 9, 9}});
  b.indices.insert(b.indices.end(), {base, base + 1, base + 2, base + 3, base + 3, base + 4});
  // A speck 1 above the middle of the collinear triangle: 1 from it, farther from all else.
  const Result<SurfaceDistance> d = surfaceDistance(speck({4, 0, 1}), b, 1000);
  ASSERT_TRUE(d.ok()) << d.message();
  EXPECT_NEAR(d->meanAB, 1.0, 1e-8);
  // b's samples all lie on the square (the degenerate triangles have no area): each is at least
  // 3 from the speck and at most sqrt(4^2 + 1^2 + 1^2).
  EXPECT_TRUE(std::isfinite(d->meanBA) && std::isfinite(d->rms) && std::isfinite(d->hausdorff));
  EXPECT_GT(d->meanBA, 3.0);
  EXPECT_LE(d->hausdorff, std::sqrt(18.0) + 1e-6);
}

TEST(SurfaceDistance, TheSameSeedGivesTheSameResultAndAnotherSeedOtherSamples) {
  const Mesh a = triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  const Mesh b = triangle({0, 0, 0.2}, {0.7, 0, 0}, {0, 0.4, 0});
  const Result<SurfaceDistance> first = surfaceDistance(a, b, 5000, 7);
  const Result<SurfaceDistance> again = surfaceDistance(a, b, 5000, 7);
  const Result<SurfaceDistance> other = surfaceDistance(a, b, 5000, 8);
  ASSERT_TRUE(first.ok() && again.ok() && other.ok());
  EXPECT_EQ(first->meanAB, again->meanAB);
  EXPECT_EQ(first->hausdorff, again->hausdorff);
  EXPECT_NE(first->meanAB, other->meanAB);
  EXPECT_NEAR(first->meanAB, other->meanAB, 0.01);  // both estimate the same mean
}

TEST(SurfaceDistance, AFarSamplerFindsWhatFarSamplesFindsAndTheFarthestSampleOfAll) {
  // The unit square against its lower-left half lifted by 0.1: that half's samples are 0.1 away,
  // the other half's up to sqrt(0.5 + 0.01).
  const Mesh original = square(4);
  const Mesh half = triangle({0, 0, 0.1}, {1, 0, 0.1}, {0, 1, 0.1});
  const Result<FarSampler> sampler = FarSampler::create(original, 3000);
  ASSERT_TRUE(sampler.ok()) << sampler.message();
  for (double limit : {0.0, 0.2, 1.0}) {
    double farthest = -1.0;
    const Result<std::vector<FarSample>> got = sampler->measure(half, limit, &farthest);
    const Result<std::vector<FarSample>> want = farSamples(original, half, 3000, limit);
    ASSERT_TRUE(got.ok() && want.ok());
    ASSERT_EQ(got->size(), want->size());
    for (std::size_t i = 0; i < got->size(); ++i) {
      EXPECT_EQ((*got)[i].point, (*want)[i].point);
      EXPECT_EQ((*got)[i].triangle, (*want)[i].triangle);
      EXPECT_EQ((*got)[i].distance, (*want)[i].distance);
    }
    // Every sample is farther than 0: the largest of limit 0's list is the farthest of all.
    const Result<std::vector<FarSample>> all = farSamples(original, half, 3000, 0.0);
    ASSERT_TRUE(all.ok());
    ASSERT_EQ(all->size(), 3000u);
    double want2 = 0.0;
    for (const FarSample& x : *all) want2 = std::max(want2, x.distance);
    EXPECT_EQ(farthest, want2);
    EXPECT_GT(farthest, 0.6);
    EXPECT_LE(farthest, std::sqrt(0.51) + 1e-12);
  }
  EXPECT_FALSE(FarSampler::create(original, 0).ok());
  EXPECT_FALSE(FarSampler::create(triangle({0, 0, 0}, {1, 1, 1}, {2, 2, 2}), 10).ok());
  EXPECT_FALSE(sampler->measure(Mesh{}, 0.1).ok());
}

TEST(SurfaceDistance, UnusableMeshesAreErrors) {
  const Mesh good = square(1);
  Mesh empty;
  Mesh ragged = good;
  ragged.indices.pop_back();
  Mesh outOfRange = good;
  outOfRange.indices[0] = 99;
  Mesh notFinite = good;
  notFinite.positions[1].y = std::numeric_limits<double>::quiet_NaN();
  const Mesh noArea = triangle({0, 0, 0}, {1, 1, 1}, {2, 2, 2});
  for (const Mesh* bad :
       std::initializer_list<const Mesh*>{&empty, &ragged, &outOfRange, &notFinite, &noArea}) {
    EXPECT_FALSE(surfaceDistance(good, *bad, 100).ok());
    EXPECT_FALSE(surfaceDistance(*bad, good, 100).ok());
  }
  EXPECT_FALSE(surfaceDistance(good, good, 0).ok());
  const Result<SurfaceDistance> r = surfaceDistance(good, noArea, 100);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("no surface area"), std::string::npos) << r.message();
}

TEST(SurfaceDistance, ARippleOverAHundredThousandTrianglesIsItsAmplitudeFromTheFlatGrid) {
  // A 224 x 224 grid (100352 triangles) rippled by at most 0.02 against a flat one of the same
  // size: every distance lies in [0, 0.02], and the ripple's crests (on grid vertices) reach it.
  // (Its time: metrics_bench.)
  const Result<SurfaceDistance> d = surfaceDistance(rippledSquare(224, 0.02), square(224), 100000);
  ASSERT_TRUE(d.ok()) << d.message();
  EXPECT_LE(d->hausdorff, 0.02 + 1e-9);
  EXPECT_GT(d->hausdorff, 0.019);
  // The mean of |z| over whole periods is 0.02 (2 / pi)^2; sampling by area (the slopes add up
  // to 3%) weighs the steep, low parts a little more.
  EXPECT_NEAR(d->meanAB, 0.02 * 4.0 / (std::numbers::pi * std::numbers::pi), 0.0005);
}

}  // namespace
}  // namespace hlod::metrics
