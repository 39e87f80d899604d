#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "RuntimeTestScene.h"
#include "hlod/runtime/FsSelector.h"
#include "hlod/runtime/FullSelector.h"
#include "hlod/runtime/LakhiaSelector.h"
#include "hlod/runtime/SseSelector.h"

namespace hlod {
namespace {

using test::makeSyntheticCity;
using test::overview;
using test::SyntheticCity;

View streetView(const SyntheticCity& c) {
  View v;
  // In the street between block rows 0 and 1, at eye height, looking along +X.
  const double y = c.blockSize + c.street * 0.5;
  v.camera.position = {-5.0, y, 1.7};
  v.camera.target = {100.0, y, 1.7};
  return v;
}

bool allFinite(const Selection& s) {
  if (!std::isfinite(s.estimatedMs) || !std::isfinite(s.estimatedCost)) return false;
  for (const LoadRequest& r : s.loadPriorities) {
    if (!std::isfinite(r.priority) || r.priority < 0.0) return false;
  }
  return true;
}

// Two blocks side by side along X (roots 0 and 1), `depth` levels below hlod_0.
Skeleton twoBlocks(int depth) {
  SyntheticCity c;
  c.blocksX = 2;
  c.blocksY = 1;
  c.depth = depth;
  return makeSyntheticCity(c);
}

class RefuseNodes final : public Residency {
 public:
  std::vector<std::uint32_t> missing;
  bool isResident(std::uint32_t n) const override {
    return std::find(missing.begin(), missing.end(), n) == missing.end();
  }
};

// measured = k * sum(cost of drawn nodes) * (1 + noise): the simulated GPU.
struct SimulatedGpu {
  double k = 2e-5;  // ms per triangle
  double noise = 0.1;
  double overheadMs = 0.0;
  std::mt19937 rng{42};
  double frame(const Skeleton& sk, const Selection& s) {
    double cost = 0.0;
    for (std::uint32_t n : s.front) cost += sk.nodes[n].cost;
    std::normal_distribution<double> d(0.0, noise);
    return std::max(0.01, overheadMs + k * cost * (1.0 + d(rng)));
  }
};

TEST(LakhiaSelector, RootTimeSlicesSumToTheAimedTime) {
  const Skeleton sk = makeSyntheticCity({});
  SelectorParams p;
  p.lakhia.vTimeInitial = 1e-4;  // the whole city at full detail would not fit the target
  LakhiaSelector sel(sk, p);
  const Selection s = sel.select(overview(sk), AllResident());
  double sum = 0.0;
  for (std::uint32_t r : sk.roots) {
    sum += sel.timeSlice(r);
    if (sel.timeSlice(r) > 0.0) {
      EXPECT_GE(sel.timeSlice(r), sel.timeNeeded(r));  // never below its own need
    }
  }
  EXPECT_NEAR(sum, p.lakhia.c_aim * sel.targetMs(), 1e-9);  // c_aim of c_targetTime
  EXPECT_TRUE(allFinite(s));
}

TEST(LakhiaSelector, UploadTimeSpentBeforeDrawingIsTakenFromTheSlices) {
  // 10 ms of uploads leave the drawing c_targetTime - 10: the root slices share c_aim of that,
  // the estimate counts the uploads, and a frame already over budget gets no NaN, only roots.
  const Skeleton sk = makeSyntheticCity({});
  SelectorParams p;
  p.lakhia.vTimeInitial = 1e-4;
  LakhiaSelector sel(sk, p);
  View v = overview(sk);
  v.spentMs = 10.0;
  const Selection s = sel.select(v, AllResident());
  double sum = 0.0;
  for (std::uint32_t r : sk.roots) sum += sel.timeSlice(r);
  EXPECT_NEAR(sum, p.lakhia.c_aim * (p.lakhia.c_targetTime - 10.0), 1e-9);
  EXPECT_DOUBLE_EQ(s.drawBudgetMs, p.lakhia.c_targetTime - 10.0);
  EXPECT_NEAR(s.estimatedMs, 10.0 + s.vTime * s.estimatedCost, 1e-9);

  for (double spent : {1e9, std::numeric_limits<double>::infinity(), -5.0,
                       std::numeric_limits<double>::quiet_NaN()}) {
    LakhiaSelector fresh(sk, p);
    v.spentMs = spent;
    const Selection t = fresh.select(v, AllResident());
    EXPECT_TRUE(allFinite(t)) << spent;
    EXPECT_GE(t.drawBudgetMs, 0.0) << spent;
    EXPECT_LE(t.drawBudgetMs, p.lakhia.c_targetTime) << spent;
    if (spent == 1e9) {
      for (std::uint32_t n : t.front) EXPECT_EQ(sk.nodes[n].parent, kNoNode);  // only hlod_0
    }
  }
}

TEST(LakhiaSelector, SlicesStopAtWhatASubtreeCanUse) {
  // With a very cheap v_time every subtree fits many times over: each root's slice is capped at
  // c_demandMargin times the need of its leaves, and the rest of the target stays unassigned.
  const Skeleton sk = makeSyntheticCity({});
  SelectorParams p;
  p.lakhia.vTimeInitial = 1e-9;
  LakhiaSelector sel(sk, p);
  sel.select(overview(sk), AllResident());
  double sum = 0.0;
  for (std::uint32_t r : sk.roots) {
    if (sel.timeSlice(r) == 0.0) continue;
    double leaves = 0.0;
    for (std::uint32_t n = 0; n < sk.nodes.size(); ++n) {
      std::uint32_t a = n;
      while (a != r && sk.nodes[a].parent != kNoNode) a = sk.nodes[a].parent;
      if (a == r && sk.nodes[n].childCount == 0) leaves += std::max(1.0, sk.nodes[n].cost);
    }
    EXPECT_NEAR(sel.timeSlice(r), 1e-9 * leaves * p.lakhia.c_demandMargin, 1e-12);
    sum += sel.timeSlice(r);
  }
  EXPECT_LT(sum, sel.targetMs());
}

TEST(LakhiaSelector, ANodeWithoutErrorIsDrawnAsALeafWhereTheStoreHasErrors) {
  // A 3D Tiles tile with geometricError 0 has children that draw the same surface: with time for
  // everything, Lakhia draws it and none of its descendants, as SSE does; its siblings refine.
  Skeleton sk = makeSyntheticCity({});
  const std::uint32_t root = sk.roots.front();
  const std::uint32_t exact = sk.nodes[root].firstChild;
  ASSERT_GT(sk.nodes[exact].childCount, 0u);
  sk.nodes[exact].geometricError = 0.0;
  SelectorParams p;
  p.lakhia.vTimeInitial = 1e-9;  // everything fits
  auto frontOf = [&](const Skeleton& skeleton) {
    LakhiaSelector sel(skeleton, p);
    Selection s;
    for (int f = 0; f < 30; ++f) s = sel.select(overview(skeleton), AllResident());
    return s.front;
  };
  auto under = [&](std::uint32_t n, std::uint32_t a) {
    for (; n != kNoNode; n = sk.nodes[n].parent)
      if (n == a) return true;
    return false;
  };
  const std::vector<std::uint32_t> front = frontOf(sk);
  EXPECT_NE(std::find(front.begin(), front.end(), exact), front.end());
  for (std::uint32_t n : front) EXPECT_FALSE(under(n, exact) && n != exact) << n;
  const std::uint32_t sibling = exact + 1;
  ASSERT_EQ(sk.nodes[sibling].parent, root);
  EXPECT_EQ(std::find(front.begin(), front.end(), sibling), front.end());  // refined past it
  // A store without errors at all (every node 0) is refined as before: 0 means unknown there.
  for (NodeInfo& n : sk.nodes) n.geometricError = 0.0;
  const std::vector<std::uint32_t> unknown = frontOf(sk);
  EXPECT_EQ(std::find(unknown.begin(), unknown.end(), exact), unknown.end());
}

TEST(LakhiaSelector, TimeSlicesOfVisibleSiblingsSumToTheParentsSlice) {
  const Skeleton sk = makeSyntheticCity({});
  SelectorParams p;
  p.lakhia.vTimeInitial = 1e-8;  // cheap: everything refines, so every group is visited
  LakhiaSelector sel(sk, p);
  // A few frames: the children's urgency builds up their hyst until the leaves are reached.
  Selection s;
  for (int f = 0; f < 12; ++f) s = sel.select(overview(sk), AllResident());
  int groups = 0;
  for (std::uint32_t n = 0; n < sk.nodes.size(); ++n) {
    const NodeInfo& info = sk.nodes[n];
    if (info.childCount == 0 || !sel.visitedLastFrame(info.firstChild)) continue;
    double sum = 0.0;
    for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c) {
      sum += sel.timeSlice(c);
    }
    EXPECT_NEAR(sum, sel.timeSlice(n), 1e-9 * std::max(1.0, sel.timeSlice(n))) << "node " << n;
    ++groups;
  }
  EXPECT_GT(groups, 10);
  EXPECT_GT(s.nodesDrawnPerLevel.back(), 0u);  // reached the leaves
}

TEST(LakhiaSelector, CameraInsideANodeBoxGivesFinitePriorities) {
  const Skeleton sk = makeSyntheticCity({});
  LakhiaSelector sel(sk);
  View v;
  v.camera.position = sk.nodes[0].bounds.centre();  // inside block 0 and some of its pieces
  v.camera.target = v.camera.position + glm::dvec3(1.0, 0.0, 0.0);
  for (int f = 0; f < 5; ++f) {
    const Selection s = sel.select(v, AllResident());
    ASSERT_TRUE(allFinite(s));
    for (std::uint32_t n = 0; n < sk.nodes.size(); ++n) {
      ASSERT_TRUE(std::isfinite(sel.hyst(n)));
      ASSERT_TRUE(std::isfinite(sel.timeSlice(n)));
    }
    sel.feedback(10.0);
  }
  // Node 0 contains the camera: its distance is c_minDistance, so it has the top priority.
  const PriorityModel model(v, sel.params().lakhia);
  const NodePriority p0 = model.evaluate(sk.nodes[0]);
  EXPECT_DOUBLE_EQ(p0.distance, sel.params().lakhia.c_minDistance);
  EXPECT_TRUE(std::isfinite(p0.priority));
  EXPECT_GT(p0.priority, 0.0);
}

TEST(LakhiaSelector, ZeroCostAndZeroBenefitNodesGiveNoNanOrInfinity) {
  Skeleton sk = makeSyntheticCity({});
  for (NodeInfo& n : sk.nodes) {
    n.cost = 0.0;
    n.staticBenefit = 0.0;
    n.numTri = 0;
  }
  LakhiaSelector sel(sk);
  const View v = overview(sk);
  for (int f = 0; f < 10; ++f) {
    const Selection s = sel.select(v, AllResident());
    ASSERT_TRUE(allFinite(s));
    sel.feedback(5.0);
    ASSERT_TRUE(std::isfinite(sel.vTime()));
  }
  // All priorities are 0 and all needs equal (the c_minCost floor): visible roots get equal
  // slices, and none is below its need.
  double first = 0.0;
  int visibleRoots = 0;
  for (std::uint32_t r : sk.roots) {
    if (sel.timeSlice(r) == 0.0) continue;
    if (first == 0.0) first = sel.timeSlice(r);
    ++visibleRoots;
    EXPECT_NEAR(sel.timeSlice(r), first, 1e-9 * first);
    EXPECT_GE(sel.timeSlice(r), sel.timeNeeded(r));
  }
  ASSERT_GT(visibleRoots, 0);
}

TEST(LakhiaSelector, InvisibleSiblingsGetNoSliceAndAreNotDrawn) {
  const SyntheticCity c;
  const Skeleton sk = makeSyntheticCity(c);
  SelectorParams p;
  p.lakhia.vTimeInitial = 1e-8;
  LakhiaSelector sel(sk, p);
  View v = streetView(c);
  v.camera.fovY = 20.0;
  const Selection s = sel.select(v, AllResident());
  const Frustum fr = v.camera.frustum();
  int invisibleVisited = 0;
  for (std::uint32_t n = 0; n < sk.nodes.size(); ++n) {
    if (fr.intersects(sk.nodes[n].bounds)) continue;
    EXPECT_EQ(sel.timeSlice(n), 0.0);
    EXPECT_EQ(std::count(s.front.begin(), s.front.end(), n), 0) << "invisible node drawn " << n;
    invisibleVisited += !s.loadPriorities.empty() && sel.priority(n) > 0.0;
  }
  EXPECT_GT(invisibleVisited, 0);  // they still have a (load) priority
  EXPECT_FALSE(s.front.empty());
  EXPECT_TRUE(allFinite(s));
}

TEST(LakhiaSelector, AllSiblingsInvisibleGivesAnEmptyFrontWithoutNan) {
  const Skeleton sk = makeSyntheticCity({});
  LakhiaSelector sel(sk);
  View v;
  v.camera.position = {-100.0, -100.0, 10.0};
  v.camera.target = {-200.0, -200.0, 10.0};  // looking away from the city
  const Selection s = sel.select(v, AllResident());
  EXPECT_TRUE(s.front.empty());
  EXPECT_EQ(s.estimatedMs, 0.0);
  EXPECT_TRUE(allFinite(s));
  sel.feedback(3.0);  // empty frame: v_time unchanged
  EXPECT_DOUBLE_EQ(sel.vTime(), sel.params().lakhia.vTimeInitial);
}

TEST(LakhiaSelector, HysteresisStaysWithinTheLimit) {
  const Skeleton sk = makeSyntheticCity({});
  LakhiaSelector sel(sk);
  SimulatedGpu gpu;
  const View v = overview(sk);
  for (int f = 0; f < 50; ++f) {
    const Selection s = sel.select(v, AllResident());
    sel.feedback(gpu.frame(sk, s));
    for (std::uint32_t n = 0; n < sk.nodes.size(); ++n) {
      ASSERT_LE(std::abs(sel.hyst(n)), sel.params().lakhia.c_hystLimit);
    }
  }
}

TEST(LakhiaSelector, VisibleChildNotResidentKeepsTheParentAndIsWanted) {
  const Skeleton sk = makeSyntheticCity({});
  SelectorParams p;
  p.lakhia.vTimeInitial = 1e-8;  // the budget would allow everything
  LakhiaSelector sel(sk, p);
  const View v = overview(sk);
  const Selection all = sel.select(v, AllResident());
  // Pick a refined root and hide one of its visible children.
  std::uint32_t root = kNoNode, child = kNoNode;
  const Frustum fr = v.camera.frustum();
  for (std::uint32_t r : sk.roots) {
    if (std::count(all.front.begin(), all.front.end(), r)) continue;
    for (std::uint32_t c = sk.nodes[r].firstChild; c < sk.nodes[r].firstChild + 3; ++c) {
      if (fr.intersects(sk.nodes[c].bounds)) child = c;
    }
    if (child != kNoNode) {
      root = r;
      break;
    }
  }
  ASSERT_NE(root, kNoNode);
  RefuseNodes residency;
  residency.missing = {child};
  LakhiaSelector sel2(sk, p);
  const Selection s = sel2.select(v, residency);
  EXPECT_EQ(std::count(s.front.begin(), s.front.end(), root), 1);
  for (std::uint32_t c = sk.nodes[root].firstChild; c < sk.nodes[root].firstChild + 3; ++c) {
    EXPECT_EQ(std::count(s.front.begin(), s.front.end(), c), 0);
  }
  EXPECT_GE(s.coarserBecauseNotResident, 1u);
  bool wanted = false;
  for (const LoadRequest& r : s.loadPriorities)
    wanted = wanted || (r.node == child && r.priority > 0);
  EXPECT_TRUE(wanted);
}

TEST(LakhiaSelector, FeedbackLoopConvergesToTheTargetWithNoisyFrameTime) {
  SyntheticCity c;
  c.blocksX = 8;
  c.blocksY = 8;
  c.depth = 4;
  const Skeleton sk = makeSyntheticCity(c);
  LakhiaSelector sel(sk);  // v_time starts 2x off the simulated GPU
  SimulatedGpu gpu;
  const View v = overview(sk);
  double sumEstErr = 0.0, sumMeasured = 0.0, sumVTimeErr = 0.0, maxMeasured = 0.0;
  int n = 0;
  for (int f = 0; f < 400; ++f) {
    const Selection s = sel.select(v, AllResident());
    const double measured = gpu.frame(sk, s);
    sel.feedback(measured);
    if (f >= 200) {
      sumEstErr += std::abs(measured - s.estimatedMs) / measured;
      sumMeasured += measured;
      maxMeasured = std::max(maxMeasured, measured);
      sumVTimeErr += std::abs(sel.vTime() - gpu.k) / gpu.k;
      ++n;
    }
  }
  EXPECT_LT(sumVTimeErr / n, 0.05) << "v_time did not converge to the simulated ms per triangle";
  EXPECT_LT(sumEstErr / n, 0.1) << "estimate does not track the measured frame time";
  // The slices and the budget fill bring the mean frame time into the fill's hysteresis band,
  // c_aim * [1 - c_fillAdd, 1 + c_fillKeep] of the target (0.95 to 1.05), give or take noise.
  const LakhiaParams& lp = sel.params().lakhia;
  EXPECT_GT(sumMeasured / n, 0.97 * lp.c_aim * (1.0 - lp.c_fillAdd) * lp.c_targetTime);
  EXPECT_LT(sumMeasured / n, 1.03 * lp.c_aim * (1.0 + lp.c_fillKeep) * lp.c_targetTime);
  EXPECT_LT(maxMeasured, 1.4 * sel.targetMs());  // 10% noise on top
}

// A still camera with 10% frame-time noise, twelve noise sequences. The selection settles:
// after the first 10 frames, changes are groups with a few % of spare time slowly earning their
// switch (urgency) and the fill making room for them, rarer and rarer. No node flickers: none
// changes back within 5 s (150 frames). Not asserted: zero toggles after frame 600 for every
// sequence; a rare excursion of the noise (one in a few) still moves a group or two.
// With benefits from geometric error (c_errorBenefit) the synthetic city's siblings, of one
// error each level, differ by 1/distance where the paper's differ by 1/distance^2: closer
// slices, more groups near their switch, and the settling takes longer (middle, quiet).
class StillCamera : public ::testing::TestWithParam<double> {};

TEST_P(StillCamera, SettlesAndNeverFlickers) {
  const bool errorBenefit = GetParam() > 0.0;
  SyntheticCity c;
  c.blocksX = 8;
  c.blocksY = 8;
  c.depth = 4;
  const Skeleton sk = makeSyntheticCity(c);
  SelectorParams p;
  p.lakhia.vTimeInitial = 2e-5;  // the simulated GPU's value: no convergence phase
  p.lakhia.c_errorBenefit = GetParam();
  const View v = overview(sk);
  int lateAll = 0, quietSequences = 0;
#ifdef HLODR_SANITIZE_BUILD
  const std::vector<unsigned> seeds = {42u, 1u, 2u, 3u};  // four sequences are the same test
#else
  const std::vector<unsigned> seeds = {42u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 10u, 11u};
#endif
  for (unsigned seed : seeds) {
    LakhiaSelector sel(sk, p);
    SimulatedGpu gpu;
    gpu.rng.seed(seed);
    std::vector<int> lastChange(sk.nodes.size(), -1000);
    std::vector<std::uint8_t> drawn(sk.nodes.size(), 0), now(sk.nodes.size(), 0);
    int early = 0, middle = 0, late = 0, flickers = 0;
    std::size_t frontSize = 0;
    for (int f = 0; f < 900; ++f) {
      const Selection s = sel.select(v, AllResident());
      sel.feedback(gpu.frame(sk, s));
      (f < 10 ? early : f < 600 ? middle : late) += int(s.upToggles + s.downToggles);
      frontSize = s.front.size();
      std::fill(now.begin(), now.end(), 0);
      for (std::uint32_t n : s.front) now[n] = 1;
      for (std::uint32_t n = 0; n < sk.nodes.size() && f >= 10; ++n) {
        if (now[n] == drawn[n]) continue;
        flickers += f - lastChange[n] < 150;
        lastChange[n] = f;
      }
      drawn.swap(now);
    }
    EXPECT_GT(early, 0) << seed;  // it did refine from hlod_0 at first
    EXPECT_LT(middle, errorBenefit ? 200 : 100) << seed;
    EXPECT_LT(late, 20) << seed;  // of ~900 drawn nodes, in 300 frames
    EXPECT_EQ(flickers, 0) << seed;
    EXPECT_GT(frontSize, 500u) << seed;  // settled by staying refined, not by giving up detail
    lateAll += late;
    quietSequences += late == 0;
  }
  EXPECT_LT(lateAll, 5 * int(seeds.size()));
  // Many sequences have no toggle at all in the last 300 frames: most with the paper's benefit.
  EXPECT_GE(quietSequences, int(seeds.size()) / (errorBenefit ? 4 : 2)) << lateAll;
}

// LakhiaSelector/StillCamera.SettlesAndNeverFlickers/0 the paper's benefit, /1 from errors.
INSTANTIATE_TEST_SUITE_P(LakhiaSelector, StillCamera, ::testing::Values(0.0, 1.0));

TEST(LakhiaSelector, ARefinementKeptFromAnEarlierViewGivesWayToOneTheNewViewNeedsMore) {
  // Two blocks, each a root of 1000 triangles over three children of 1000. The budget pays for
  // one block refined (4000 triangles), not both (6000). The walk refines nothing anew
  // (c_hystRefine), so the budget fill alone decides which block is refined.
  const Skeleton sk = twoBlocks(1);
  ASSERT_EQ(sk.roots.size(), 2u);
  const std::uint32_t a = sk.roots[0], b = sk.roots[1];
  SelectorParams p;
  p.lakhia.vTimeInitial = 1e-3;  // ms per triangle, the simulated GPU's
  p.lakhia.c_targetTime = 4.5;
  p.lakhia.c_hystRefine = 1000000;
  LakhiaSelector sel(sk, p);
  SimulatedGpu gpu;
  gpu.k = 1e-3;
  gpu.noise = 0.0;
  auto settle = [&](const View& v) {
    Selection s;
    for (int f = 0; f < 100; ++f) {
      s = sel.select(v, AllResident());
      sel.feedback(gpu.frame(sk, s));
    }
    return s;
  };
  auto drawn = [](const Selection& s, std::uint32_t n) {
    return std::find(s.front.begin(), s.front.end(), n) != s.front.end();
  };
  View nearA;  // before block a, looking along +X over both
  nearA.camera.position = {-30.0, 20.0, 30.0};
  nearA.camera.target = {92.0, 20.0, 0.0};
  View nearB;  // beyond block b, looking back along -X
  nearB.camera.position = {122.0, 20.0, 30.0};
  nearB.camera.target = {0.0, 20.0, 0.0};
  const Selection first = settle(nearA);
  EXPECT_TRUE(drawn(first, sk.nodes[a].firstChild));
  EXPECT_TRUE(drawn(first, b));
  EXPECT_GT(sel.priority(a), sel.priority(b));
  // The camera moves to the other end: the block now near is refined, the far one given back.
  const Selection second = settle(nearB);
  EXPECT_GT(sel.priority(b), sel.priority(a));
  EXPECT_TRUE(drawn(second, sk.nodes[b].firstChild));
  EXPECT_TRUE(drawn(second, a));
  EXPECT_LE(gpu.frame(sk, second), p.lakhia.c_targetTime);
}

TEST(LakhiaSelector, WithErrorsKnownABenefitFollowsTheErrorItRemoves) {
  const Skeleton even = twoBlocks(2);
  ASSERT_EQ(even.roots.size(), 2u);
  const std::uint32_t a = even.roots[0], b = even.roots[1];
  ASSERT_GT(even.nodes[a].geometricError, 0.0);
  Skeleton rugged = even;
  rugged.nodes[a].geometricError *= 10.0;  // ten times the error at the same size and place
  auto ratio = [&](const Skeleton& sk, double errorBenefit) {
    SelectorParams p;
    p.lakhia.c_errorBenefit = errorBenefit;
    LakhiaSelector sel(sk, p);
    sel.select(overview(sk), AllResident());
    EXPECT_GT(sel.priority(b), 0.0);
    return sel.priority(a) / sel.priority(b);
  };
  // Benefit = projected error * vis * foreshorten: ten times the error, ten times the priority.
  EXPECT_NEAR(ratio(rugged, 1.0), 10.0 * ratio(even, 1.0), 1e-9 * ratio(even, 1.0));
  // The paper's benefit (eq. 2, 3) does not see the error.
  EXPECT_DOUBLE_EQ(ratio(rugged, 0.0), ratio(even, 0.0));
  // The default (-1) takes the benefit from errors where the store is another's tileset, and
  // the paper's on a store hlodr built.
  EXPECT_DOUBLE_EQ(ratio(rugged, -1.0), ratio(rugged, 0.0));
  Skeleton tileset = rugged;
  tileset.params.simplifier = kTilesetSimplifier;
  EXPECT_DOUBLE_EQ(ratio(tileset, -1.0), ratio(rugged, 1.0));
  EXPECT_DOUBLE_EQ(ratio(tileset, 0.0), ratio(rugged, 0.0));
  EXPECT_EQ(SelectorParams{}.lakhia.c_errorBenefit, -1.0);
}

TEST(LakhiaSelector, TogglesCountRefinementsAndCoarsenings) {
  const Skeleton sk = makeSyntheticCity({});
  SelectorParams p;
  p.lakhia.vTimeInitial = 1e-8;
  LakhiaSelector sel(sk, p);
  const View v = overview(sk);
  Selection s = sel.select(v, AllResident());
  EXPECT_EQ(s.upToggles, 0u);  // first frame: no previous frame to compare with
  sel.setTargetMs(1e-9);       // nothing fits any more: children coarsen within a few frames
  std::uint32_t down = 0;
  for (int f = 0; f < 20; ++f) down += sel.select(v, AllResident()).downToggles;
  EXPECT_GT(down, 0u);
  s = sel.select(v, AllResident());
  EXPECT_EQ(s.nodesDrawnPerLevel[0], s.front.size());  // back to hlod_0 only
  sel.setTargetMs(1e9);
  std::uint32_t up = 0;
  for (int f = 0; f < 20; ++f) up += sel.select(v, AllResident()).upToggles;
  EXPECT_GT(up, 0u);
}

TEST(LakhiaSelector, EstimatedTimeIsVTimeTimesDrawnCost) {
  const Skeleton sk = makeSyntheticCity({});
  LakhiaSelector sel(sk);
  const Selection s = sel.select(overview(sk), AllResident());
  double cost = 0.0;
  std::uint64_t tris = 0;
  for (std::uint32_t n : s.front) {
    cost += sk.nodes[n].cost;
    tris += sk.nodes[n].numTri;
  }
  EXPECT_DOUBLE_EQ(s.estimatedCost, cost);
  EXPECT_DOUBLE_EQ(s.estimatedMs, s.vTime * cost);
  EXPECT_EQ(s.triangles, tris);
}

TEST(PriorityModel, FrustumVisFallsLinearlyOutsideTheFrustum) {
  View v;
  v.camera.position = {0, 0, 0};
  v.camera.target = {0, 1, 0};
  v.camera.fovY = 90.0;
  v.camera.aspect = 1.0;
  LakhiaParams p;
  const PriorityModel model(v, p);
  NodeInfo n;
  n.bounds.min = {-1, 10, -1};
  n.bounds.max = {1, 12, 1};  // diagonal sqrt(12)
  EXPECT_DOUBLE_EQ(model.evaluate(n).frustumVis, 1.0);
  EXPECT_DOUBLE_EQ(model.evaluate(n).vis, 1.0 + p.c_vis);
  // Behind the camera by 1 unit beyond the near plane: outside by (ymax - near)... measure it.
  NodeInfo behind = n;
  behind.bounds.min = {-1, -3, -1};
  behind.bounds.max = {1, -1.1, 1};
  const double outside = v.camera.frustum().distanceOutside(behind.bounds);
  EXPECT_NEAR(outside, 1.1 + v.camera.nearPlane, 1e-9);
  const double diag = glm::length(behind.bounds.size());
  EXPECT_NEAR(model.evaluate(behind).frustumVis, 1.0 - outside / diag, 1e-9);
  NodeInfo far = n;
  far.bounds.min = {-1, -30, -1};
  far.bounds.max = {1, -28, 1};
  EXPECT_EQ(model.evaluate(far).frustumVis, 0.0);
  EXPECT_DOUBLE_EQ(model.evaluate(far).vis, 1.0);
}

TEST(PriorityModel, FacingSurfacesHaveMoreBenefitThanSurfacesFacingAway) {
  View v;
  v.camera.position = {0, 0, 0};
  v.camera.target = {0, 1, 0};
  LakhiaParams p;
  const PriorityModel model(v, p);
  NodeInfo facing;
  facing.bounds.min = {-1, 10, -1};
  facing.bounds.max = {1, 11, 1};
  facing.staticBenefit = 100.0;
  facing.cost = 10.0;
  facing.avgNormal = {0, -1, 0};  // points back at the camera
  NodeInfo away = facing;
  away.avgNormal = {0, 1, 0};
  EXPECT_DOUBLE_EQ(model.evaluate(facing).foreshorten, 1.0 + p.c_fore);
  EXPECT_DOUBLE_EQ(model.evaluate(away).foreshorten, 1.0 - p.c_fore);
  EXPECT_GT(model.evaluate(facing).priority, model.evaluate(away).priority);
}

TEST(PriorityModel, VelocityLookaheadRaisesPriorityOfNodesAhead) {
  View v;
  v.camera.position = {0, 0, 0};
  v.camera.target = {0, 1, 0};
  NodeInfo ahead;
  ahead.bounds.min = {-1, 20, -1};
  ahead.bounds.max = {1, 21, 1};
  ahead.staticBenefit = 100.0;
  ahead.cost = 10.0;
  LakhiaParams p;
  const double still = PriorityModel(v, p).evaluate(ahead).priority;
  v.velocity = {0, 20, 0};  // 0.5 s lookahead: 10 units closer
  const NodePriority moving = PriorityModel(v, p).evaluate(ahead);
  EXPECT_NEAR(moving.distance, 10.0, 1e-9);
  EXPECT_GT(moving.priority, still);
}

TEST(VTimeFeedback, ConvergesWithoutOvershootFromFarOff) {
  VTimeFeedback fb(1e-3, 0.2, 4.0);
  const double k = 1e-5, cost = 1e6;
  double prev = fb.vTime();
  for (int i = 0; i < 100; ++i) {
    fb.update(k * cost, cost);
    EXPECT_LE(fb.vTime(), prev);  // monotone: no oscillation
    EXPECT_GE(fb.vTime(), k * (1 - 1e-12));
    prev = fb.vTime();
  }
  EXPECT_NEAR(fb.vTime(), k, k * 1e-3);
}

TEST(VTimeFeedback, NoisyFrameTimesKeepVTimeNearTheTruth) {
  VTimeFeedback fb(1e-5, 0.2, 4.0);
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 0.2);
  const double k = 3e-5, cost = 1e5;
  double maxErr = 0.0;
  for (int i = 0; i < 500; ++i) {
    fb.update(k * cost * std::max(0.1, 1.0 + noise(rng)), cost);
    if (i > 100) maxErr = std::max(maxErr, std::abs(fb.vTime() - k) / k);
  }
  EXPECT_LT(maxErr, 0.25);
}

TEST(VTimeFeedback, OneOutlierFrameMovesVTimeByAtMostMaxRatioPowGain) {
  VTimeFeedback fb(1e-5, 0.2, 4.0);
  fb.update(1e6, 1.0);  // a 1000-second frame
  EXPECT_NEAR(fb.vTime(), 1e-5 * std::pow(4.0, 0.2), 1e-12);
  fb.update(std::nan(""), 1.0);
  fb.update(1.0, 0.0);
  fb.update(-1.0, 10.0);
  EXPECT_NEAR(fb.vTime(), 1e-5 * std::pow(4.0, 0.2), 1e-12);
}

TEST(VTimeFeedback, ALoneOutlierFrameIsDroppedAndAChangeOfTwoFramesFollowed) {
  const double k = 2e-5, cost = 1e5;
  VTimeFeedback fb(k, 0.2, 4.0);
  for (int i = 0; i < 5; ++i) fb.update(k * cost, cost);
  fb.update(3.0 * k * cost, cost);  // one frame three times as slow: the median ignores it
  EXPECT_NEAR(fb.vTime(), k, k * 1e-9);
  for (int i = 0; i < 2; ++i) {  // until it leaves the last three
    fb.update(k * cost, cost);
    EXPECT_NEAR(fb.vTime(), k, k * 1e-9);
  }
  // The scene got 50% dearer for good: the second such frame moves v_time by 1.5^gain.
  fb.update(1.5 * k * cost, cost);
  EXPECT_NEAR(fb.vTime(), k, k * 1e-9);
  fb.update(1.5 * k * cost, cost);
  EXPECT_NEAR(fb.vTime(), k * std::pow(1.5, 0.2), k * 1e-9);
  fb.set(3 * k);  // forgets the observations: the next frame counts alone
  fb.update(k * cost, cost);
  EXPECT_NEAR(fb.vTime(), 3 * k * std::pow(1.0 / 3.0, 0.2), k * 1e-9);
}

TEST(SelectorParams, SetByNameWithClearErrors) {
  SelectorParams p;
  ASSERT_TRUE(setSelectorParams(p, "c_aim=0.9,c_vis=2.5,c_hystRefine=0,ssePixels=8").ok());
  EXPECT_EQ(p.lakhia.c_aim, 0.9);
  EXPECT_EQ(p.lakhia.c_vis, 2.5);
  EXPECT_EQ(p.lakhia.c_hystRefine, 0);
  EXPECT_EQ(p.ssePixels, 8.0);
  ASSERT_TRUE(setSelectorParams(p, "").ok());                    // nothing to set
  ASSERT_TRUE(setSelectorParam(p, "c_hystInitial", -2.0).ok());  // a counter may start below 0
  const SelectorParams before = p;
  for (const char* bad :
       {"c_nope=1", "c_aim", "=1", "c_aim=", "c_aim=x", "c_aim=1x", "c_aim=-1", "c_vis=nan",
        "c_aim=inf", "ssePixels=0", "c_hystRefine=1.5", "c_aim=1,,c_vis=2"}) {
    const Status s = setSelectorParams(p, bad);
    EXPECT_FALSE(s.ok()) << bad;
  }
  EXPECT_EQ(p.lakhia.c_aim, before.lakhia.c_aim);  // a list with an error sets nothing
  EXPECT_NE(setSelectorParams(p, "c_nope=1").message().find("c_fillKeep"), std::string::npos);
}

TEST(SelectorParams, AValueOutsideItsRangeIsAnErrorNamingTheConstantAndItsRange) {
  SelectorParams p;
  struct Case {
    const char* list;
    const char* names;
  };
  for (const Case& c :
       {Case{"c_fore=1.5", "c_fore: 1.5 is outside its range 0..0.99"},
        Case{"feedbackGain=0", "feedbackGain: 0 is outside its range 0.001..1"},
        Case{"c_aim=2", "c_aim: 2 is outside its range 0.1..1.5"},
        Case{"ssePixels=5000", "ssePixels: 5000 is outside its range 0.1..1000"},
        Case{"splats=0.5", "(a whole number)"}, Case{"c_fillAdd=0.95", "c_fillAdd"}}) {
    const Status s = setSelectorParams(p, c.list);
    ASSERT_FALSE(s.ok()) << c.list;
    EXPECT_NE(s.message().find(c.names), std::string::npos) << s.message();
  }
  // The defaults are inside their ranges: setting each to its default is no error.
  const SelectorParams d;
  const LakhiaParams& l = d.lakhia;
  for (const auto& [name, value] : {std::pair{"c_vis", l.c_vis},
                                    {"c_visFalloff", l.c_visFalloff},
                                    {"c_fore", l.c_fore},
                                    {"c_velocity", l.c_velocity},
                                    {"c_minDistance", l.c_minDistance},
                                    {"c_minCost", l.c_minCost},
                                    {"c_hystLimit", l.c_hystLimit},
                                    {"c_hystSwitch", l.c_hystSwitch},
                                    {"c_hystInitial", l.c_hystInitial},
                                    {"c_hystRefine", double(l.c_hystRefine)},
                                    {"vTimeInitial", l.vTimeInitial},
                                    {"feedbackGain", l.feedbackGain},
                                    {"feedbackMaxRatio", l.feedbackMaxRatio},
                                    {"feedbackJumpRatio", l.feedbackJumpRatio},
                                    {"c_shed", l.c_shed},
                                    {"c_demandMargin", l.c_demandMargin},
                                    {"c_aim", l.c_aim},
                                    {"c_fillKeep", l.c_fillKeep},
                                    {"c_fillAdd", l.c_fillAdd},
                                    {"c_fillFast", l.c_fillFast},
                                    {"c_fillGain", l.c_fillGain},
                                    {"ssePixels", d.ssePixels},
                                    {"splatPixels", d.splatPixels},
                                    {"c_splat", d.c_splat},
                                    {"c_occludedLoad", d.c_occludedLoad},
                                    {"c_occludedKeepFrames", d.c_occludedKeepFrames}})
    EXPECT_TRUE(setSelectorParam(p, name, value).ok()) << name;
  // A fraction is no switch: it takes any value in its range, and is set.
  ASSERT_TRUE(setSelectorParams(p, "c_occludedLoad=0.25,c_occludedKeepFrames=12").ok());
  EXPECT_EQ(p.c_occludedLoad, 0.25);
  EXPECT_EQ(p.c_occludedKeepFrames, 12.0);
  EXPECT_FALSE(setSelectorParams(p, "c_occludedLoad=1.5").ok());
}

TEST(SseSelector, RefinesMoreWithASmallerPixelThreshold) {
  const Skeleton sk = makeSyntheticCity({});
  const View v = overview(sk);
  SelectorParams coarse, fine;
  coarse.ssePixels = 64.0;
  fine.ssePixels = 1.0;
  SseSelector a(sk, coarse), b(sk, fine);
  const Selection sa = a.select(v, AllResident());
  const Selection sb = b.select(v, AllResident());
  EXPECT_LT(sa.triangles, sb.triangles);
  // Every drawn non-leaf node is within the threshold.
  for (std::uint32_t n : sa.front) {
    if (!sk.isLeaf(n)) {
      EXPECT_LE(SseSelector::screenSpaceError(sk.nodes[n], v, 1.0), 64.0);
    }
  }
  EXPECT_TRUE(allFinite(sa));
}

TEST(SseSelector, FarCameraDrawsOnlyHlod0) {
  const Skeleton sk = makeSyntheticCity({});
  View v = overview(sk);
  v.camera.position = v.camera.target + glm::dvec3(0, -1e5, 1e5);
  v.camera.farPlane = 1e7;
  SseSelector sel(sk);
  const Selection s = sel.select(v, AllResident());
  EXPECT_EQ(s.nodesDrawnPerLevel[0], sk.roots.size());
  EXPECT_EQ(s.front.size(), sk.roots.size());
}

TEST(FsSelector, StaysWithinTheBudgetAndUsesMoreDetailWithMoreBudget) {
  const Skeleton sk = makeSyntheticCity({});
  const View v = overview(sk);
  SelectorParams small, large;
  small.lakhia.vTimeInitial = large.lakhia.vTimeInitial = 1e-5;
  small.lakhia.c_targetTime = 0.5;  // 50k triangles
  large.lakhia.c_targetTime = 2.0;
  FsSelector a(sk, small), b(sk, large);
  const Selection sa = a.select(v, AllResident());
  const Selection sb = b.select(v, AllResident());
  EXPECT_LE(sa.estimatedMs, 0.5 + 1e-9);
  EXPECT_LE(sb.estimatedMs, 2.0 + 1e-9);
  EXPECT_LT(sa.triangles, sb.triangles);
  EXPECT_GT(sb.estimatedMs, 1.5);  // greedy fills the budget closely on this fine tree
}

TEST(FullSelector, DrawsEveryVisibleLeafWhenAllAreResident) {
  const Skeleton sk = makeSyntheticCity({});
  const View v = overview(sk);
  FullSelector sel(sk);
  const Selection s = sel.select(v, AllResident());
  const Frustum fr = v.camera.frustum();
  std::size_t visibleLeaves = 0;
  for (std::uint32_t n = 0; n < sk.nodes.size(); ++n) {
    if (!sk.isLeaf(n) || !fr.intersects(sk.nodes[n].bounds)) continue;
    // Visible leaves of visible ancestors (boxes nest, so all of them here).
    ++visibleLeaves;
  }
  EXPECT_EQ(s.front.size(), visibleLeaves);
  for (std::uint32_t n : s.front) EXPECT_TRUE(sk.isLeaf(n));
}

TEST(FullSelector, ReplacesANonResidentLeafByItsResidentParent) {
  const Skeleton sk = makeSyntheticCity({});
  const View v = overview(sk);
  FullSelector sel(sk);
  const Selection all = sel.select(v, AllResident());
  const std::uint32_t leaf = all.front.front();
  RefuseNodes res;
  res.missing = {leaf};
  const Selection s = sel.select(v, res);
  EXPECT_EQ(std::count(s.front.begin(), s.front.end(), leaf), 0);
  EXPECT_EQ(std::count(s.front.begin(), s.front.end(), sk.nodes[leaf].parent), 1);
  EXPECT_EQ(s.coarserBecauseNotResident, 1u);
  EXPECT_EQ(s.downToggles, 1u);
}

TEST(SelectorFactory, MakesEachSelectorByNameAndRejectsUnknownNames) {
  const Skeleton sk = makeSyntheticCity({});
  for (const char* name : {"lakhia", "sse", "fs", "full"}) {
    auto s = makeSelector(name, sk);
    ASSERT_TRUE(s.ok()) << name;
    EXPECT_EQ(s.value()->name(), name);
    EXPECT_FALSE(s.value()->select(overview(sk), AllResident()).front.empty());
  }
  auto bad = makeSelector("lod", sk);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("lakhia"), std::string::npos);
}

TEST(SelectorFactory, EmptySkeletonSelectsNothing) {
  const Skeleton sk;
  for (const char* name : {"lakhia", "sse", "fs", "full"}) {
    auto s = makeSelector(name, sk);
    ASSERT_TRUE(s.ok());
    const Selection sel = s.value()->select(View{}, AllResident());
    EXPECT_TRUE(sel.front.empty());
  }
}

}  // namespace
}  // namespace hlod
