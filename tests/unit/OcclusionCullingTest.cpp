// Occlusion culling without GL (hlod/runtime/OcclusionCulling.h): the query plan and the
// visibility it keeps, the selectors with a visibility oracle, and the frame loop with a
// simulated GPU whose queries answer from an oracle (SimulatedRenderer::hidden).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "RuntimeTestScene.h"
#include "SimulatedRenderer.h"
#include "hlod/runtime/FrameDriver.h"
#include "hlod/runtime/OcclusionAuto.h"
#include "hlod/runtime/OcclusionCulling.h"

using namespace hlod;
using hlod::test::SimulatedRenderer;

namespace {

// Three nodes: a root (0) with two leaf children (1, 2); and a lone root (3).
Skeleton smallTree() {
  Skeleton sk;
  auto node = [&](std::uint32_t parent, glm::dvec3 lo, glm::dvec3 hi) {
    NodeInfo n;
    n.parent = parent;
    n.bounds.min = lo;
    n.bounds.max = hi;
    n.centre = n.bounds.centre();
    n.numTri = 100;
    n.cost = 100;
    sk.nodes.push_back(n);
  };
  node(kNoNode, {0, 0, 0}, {2, 1, 1});
  node(0, {0, 0, 0}, {1, 1, 1});
  node(0, {1, 0, 0}, {2, 1, 1});
  node(kNoNode, {5, 0, 0}, {6, 1, 1});
  sk.nodes[0].firstChild = 1;
  sk.nodes[0].childCount = 2;
  sk.nodes[1].level = sk.nodes[2].level = 1;
  sk.roots = {0, 3};
  return sk;
}

OcclusionResult answer(std::vector<std::uint32_t> nodes, std::uint64_t samples) {
  return {std::move(nodes), samples, true};
}

std::set<std::uint32_t> boxNodes(const OcclusionPlan& p) {
  std::set<std::uint32_t> s;
  for (const auto& b : p.boxBatches) s.insert(b.begin(), b.end());
  return s;
}

}  // namespace

TEST(OcclusionCulling, TheFirstFrameQueriesEveryDrawAndHidesNothing) {
  const Skeleton sk = smallTree();
  OcclusionCulling oc(sk);
  for (std::uint32_t n = 0; n < 4; ++n) EXPECT_FALSE(oc.occluded(n));
  const std::vector<std::uint32_t> front = {1, 2, 3};
  const OcclusionPlan p = oc.plan(front, {});
  EXPECT_EQ(p.queryDraw, (std::vector<std::uint8_t>{1, 1, 1}));
  EXPECT_TRUE(p.boxBatches.empty());
  EXPECT_EQ(p.queries(), 3u);
}

TEST(OcclusionCulling, ADrawFoundHiddenIsOccludedNextFrameAndOnlyItsBoxIsQueried) {
  const Skeleton sk = smallTree();
  OcclusionCulling oc(sk);
  const std::vector<std::uint32_t> front = {0, 3};
  oc.plan(front, {});
  const std::vector<OcclusionResult> r = {answer({0}, 250), answer({3}, 0)};
  oc.receive(r);
  EXPECT_FALSE(oc.occluded(0));
  EXPECT_TRUE(oc.occluded(3));
  const std::vector<std::uint32_t> front2 = {0}, hidden2 = {3};
  const OcclusionPlan p = oc.plan(front2, hidden2);
  // Node 0 was just found visible: not queried again this frame (its re-test is jittered).
  EXPECT_EQ(boxNodes(p), (std::set<std::uint32_t>{3}));
  EXPECT_EQ(oc.samples(0), 250u);
}

TEST(OcclusionCulling, AVisibleNodeIsRetestedWithinTheJitterThenEveryNavFrames) {
  const Skeleton sk = smallTree();
  OcclusionParams params;
  params.c_visibleFrames = 4;
  OcclusionCulling oc(sk, params);
  const std::vector<std::uint32_t> front = {3};
  std::vector<std::uint32_t> tested;
  for (std::uint32_t f = 1; f <= 16; ++f) {
    const OcclusionPlan p = oc.plan(front, {});
    if (p.queryDraw[0]) {
      tested.push_back(f);
      const std::vector<OcclusionResult> r = {answer({3}, 10)};
      oc.receive(r);
    }
  }
  ASSERT_GE(tested.size(), 4u);
  EXPECT_EQ(tested[0], 1u);                    // unknown: queried at once
  EXPECT_LE(tested[1] - tested[0], 4u);        // the first interval: 1 + jitter in [0, 4)
  for (std::size_t i = 2; i < tested.size(); ++i) EXPECT_EQ(tested[i] - tested[i - 1], 4u);
}

TEST(OcclusionCulling, AHiddenAnswerIsTrustedForTrustFramesOnly) {
  const Skeleton sk = smallTree();
  OcclusionCulling oc(sk);  // c_trustFrames = 2
  const std::vector<std::uint32_t> front = {3};
  oc.plan(front, {});
  const std::vector<OcclusionResult> r = {answer({3}, 0)};
  oc.receive(r);
  EXPECT_TRUE(oc.occluded(3));
  oc.plan({}, {});  // frame 2: node 3 not reached (say its ancestor hid it), not queried
  EXPECT_TRUE(oc.occluded(3));
  oc.plan({}, {});  // frame 3: the answer of frame 1 is now 3 frames old
  EXPECT_FALSE(oc.occluded(3));
}

TEST(OcclusionCulling, ABatchThatComesBackVisibleMakesItsNodesUnknownAndDrawn) {
  const Skeleton sk = smallTree();
  OcclusionCulling oc(sk);
  const std::vector<std::uint32_t> front = {1, 2, 3};
  oc.plan(front, {});
  const std::vector<OcclusionResult> hide = {answer({1}, 0), answer({2}, 0), answer({3}, 0)};
  oc.receive(hide);
  oc.plan({}, std::vector<std::uint32_t>{3});
  const std::vector<OcclusionResult> batch = {answer({1, 2}, 7)};
  oc.receive(batch);
  EXPECT_FALSE(oc.occluded(1));
  EXPECT_FALSE(oc.occluded(2));
  const std::vector<std::uint32_t> front2 = {1, 2};
  const OcclusionPlan p = oc.plan(front2, {});
  EXPECT_EQ(p.queryDraw, (std::vector<std::uint8_t>{1, 1}));  // each queried with its draw
}

TEST(OcclusionCulling, AnUnansweredQueryCountsAsVisible) {
  const Skeleton sk = smallTree();
  OcclusionCulling oc(sk);
  const std::vector<std::uint32_t> front = {3};
  oc.plan(front, {});
  const std::vector<OcclusionResult> hide = {answer({3}, 0)};
  oc.receive(hide);
  ASSERT_TRUE(oc.occluded(3));
  oc.plan({}, std::vector<std::uint32_t>{3});
  const std::vector<OcclusionResult> none = {{{3}, 0, false}};  // box crossed the near plane
  oc.receive(none);
  EXPECT_FALSE(oc.occluded(3));
}

TEST(OcclusionCulling, ANodeWhoseReachedChildrenAreAllHiddenIsQueriedInTheirPlace) {
  const Skeleton sk = smallTree();
  OcclusionCulling oc(sk);
  const std::vector<std::uint32_t> front = {1, 2, 3};
  oc.plan(front, {});
  const std::vector<OcclusionResult> r = {answer({1}, 0), answer({2}, 0), answer({3}, 9)};
  oc.receive(r);
  // The walk reaches 0, refines it, finds both children hidden.
  const std::vector<std::uint32_t> front2 = {3}, hidden2 = {1, 2};
  const OcclusionPlan p = oc.plan(front2, hidden2);
  EXPECT_EQ(boxNodes(p), (std::set<std::uint32_t>{0}));
  EXPECT_EQ(oc.counters().pulledUp, 1u);
  // Hidden too: next frame the walk stops at 0, one query for the subtree.
  const std::vector<OcclusionResult> r2 = {answer({0}, 0)};
  oc.receive(r2);
  EXPECT_TRUE(oc.occluded(0));
}

TEST(OcclusionCulling, WhenAPulledUpBoxShowsItsChildrenAreDrawnThenQueriedOneByOne) {
  const Skeleton sk = smallTree();
  OcclusionCulling oc(sk);
  const std::vector<std::uint32_t> front = {1, 2};
  oc.plan(front, {});
  const std::vector<OcclusionResult> r = {answer({1}, 0), answer({2}, 0)};
  oc.receive(r);
  oc.plan({}, std::vector<std::uint32_t>{1, 2});  // pulled up: 0 queried
  const std::vector<OcclusionResult> r2 = {answer({0}, 5)};  // 0's box shows
  oc.receive(r2);
  // Their answers predate their parent's showing: they may be in view now, and are drawn (each
  // with its draw queried) rather than left out on that old answer.
  EXPECT_FALSE(oc.occluded(1));
  EXPECT_FALSE(oc.occluded(2));
  const OcclusionPlan p = oc.plan(front, {});
  EXPECT_EQ(p.queryDraw, (std::vector<std::uint8_t>{1, 1}));
  // Still hidden behind it: from now on they are queried themselves, not pulled up into a box
  // that shows (which would have them drawn every other frame).
  const std::vector<OcclusionResult> r3 = {answer({1}, 0), answer({2}, 0)};
  oc.receive(r3);
  ASSERT_TRUE(oc.occluded(1) && oc.occluded(2));
  const OcclusionPlan p2 = oc.plan({}, std::vector<std::uint32_t>{1, 2});
  EXPECT_EQ(boxNodes(p2), (std::set<std::uint32_t>{1, 2}));
  EXPECT_EQ(oc.counters().pulledUp, 0u);
}

TEST(OcclusionCulling, KeepProbabilityAndMultiquerySizesFollowChcPlusPlus) {
  EXPECT_NEAR(OcclusionCulling::keepProbability(1), 0.99 - 0.7 * std::exp(-1.0), 1e-12);
  EXPECT_NEAR(OcclusionCulling::keepProbability(0), 0.29, 1e-12);
  // Nodes hidden 1 frame (p = 0.73): |M|/(1 + (1 - p^m) m) peaks at m = 3; 10 frames: m = 11.
  const std::vector<double> one(7, OcclusionCulling::keepProbability(1));
  EXPECT_EQ(OcclusionCulling::batchSizes(one, 32), (std::vector<std::size_t>{3, 3, 1}));
  const std::vector<double> ten(30, OcclusionCulling::keepProbability(10));
  EXPECT_EQ(OcclusionCulling::batchSizes(ten, 32), (std::vector<std::size_t>{11, 11, 8}));
  EXPECT_EQ(OcclusionCulling::batchSizes(ten, 4),
            (std::vector<std::size_t>{4, 4, 4, 4, 4, 4, 4, 2}));
}

TEST(OcclusionCulling, LongerHiddenNodesAreBatchedFirstAndNewOnesAlone) {
  const Skeleton sk = smallTree();
  OcclusionCulling oc(sk);
  const std::vector<std::uint32_t> all = {1, 2, 3};
  oc.plan(all, {});
  // 3 is hidden for three frames, 1 and 2 for one.
  for (int i = 0; i < 3; ++i) {
    const std::vector<OcclusionResult> r = {answer({3}, 0)};
    oc.receive(r);
    oc.plan({}, std::vector<std::uint32_t>{3});
  }
  const std::vector<OcclusionResult> r = {answer({3}, 0), answer({1}, 0), answer({2}, 0)};
  oc.receive(r);
  ASSERT_TRUE(oc.occluded(1) && oc.occluded(3));
  const OcclusionPlan p = oc.plan({}, std::vector<std::uint32_t>{1, 3});
  ASSERT_FALSE(p.boxBatches.empty());
  EXPECT_EQ(p.boxBatches.front().front(), 3u);  // most likely to stay hidden first
}

TEST(OcclusionAuto, TurnsCullingOffWhenTheBoxPassCostsMoreThanItSavesAndTriesAgainLater) {
  OcclusionAutoParams params;
  params.c_settleFrames = 3;
  params.c_offFrames = 5;
  OcclusionAuto a(OcclusionMode::Auto, params);
  EXPECT_TRUE(a.active());
  for (int i = 0; i < 3; ++i) a.update(true, 0.1, 1.0);  // saves 0.1 ms, costs 1 ms
  EXPECT_FALSE(a.active());
  for (int i = 0; i < 4; ++i) a.update(false, 0, 0);
  EXPECT_FALSE(a.active());
  a.update(false, 0, 0);
  EXPECT_TRUE(a.active());
  for (int i = 0; i < 10; ++i) a.update(true, 5.0, 1.0);  // pays
  EXPECT_TRUE(a.active());
}

TEST(OcclusionAuto, OnAndOffAreFixed) {
  OcclusionAuto on(OcclusionMode::On), off(OcclusionMode::Off);
  for (int i = 0; i < 20; ++i) on.update(true, 0.0, 10.0), off.update(false, 0, 0);
  EXPECT_TRUE(on.active());
  EXPECT_FALSE(off.active());
  EXPECT_FALSE(parseOcclusionMode("sometimes").ok());
  EXPECT_EQ(*parseOcclusionMode("auto"), OcclusionMode::Auto);
}

namespace {

// A visibility oracle for the selectors: the nodes listed are hidden.
struct Hidden final : OcclusionOracle {
  std::set<std::uint32_t> nodes;
  bool occluded(std::uint32_t n) const override { return nodes.count(n) > 0; }
};

// Row 0 of the synthetic city seen from the street in front of it.
View streetView() {
  View v;
  v.camera.position = {-5.0, 46.0, 1.7};
  v.camera.target = {100.0, 46.0, 5.0};
  v.viewportWidth = 640;
  v.viewportHeight = 360;
  v.camera.aspect = 640.0 / 360.0;
  return v;
}

}  // namespace

TEST(OcclusionSelectors, AnOccludedNodeIsLeftOutWithItsSubtreeByEverySelector) {
  const Skeleton sk = test::makeSyntheticCity({});
  for (const char* name : {"lakhia", "sse", "fs", "full"}) {
    SCOPED_TRACE(name);
    SelectorParams params;
    params.lakhia.c_targetTime = 1e4;  // room for everything visible
    auto sel = std::move(*makeSelector(name, sk, params));
    sel->setVTime(1e-5);
    View v = streetView();
    const Selection before = sel->select(v, AllResident{});
    ASSERT_FALSE(before.front.empty());
    // Hide the block of the first front node: its hlod_0 and everything below.
    const std::uint32_t block = sk.nodes[before.front.front()].block;
    const std::uint32_t root = sk.roots[block];
    Hidden hidden;
    hidden.nodes.insert(root);
    v.occlusion = &hidden;
    auto fresh = std::move(*makeSelector(name, sk, params));
    fresh->setVTime(1e-5);
    const Selection s = fresh->select(v, AllResident{});
    EXPECT_EQ(s.occluded, std::vector<std::uint32_t>{root});
    EXPECT_EQ(s.occludedTriangles, sk.nodes[root].numTri);
    for (std::uint32_t n : s.front) EXPECT_NE(sk.nodes[n].block, block);
    // Its load priority drops by c_occludedLoad.
    auto priorityOf = [&](const Selection& of) {
      double p = -1.0;
      for (const LoadRequest& r : of.loadPriorities)
        if (r.node == root) p = std::max(p, r.priority);
      return p;
    };
    EXPECT_DOUBLE_EQ(priorityOf(s), params.c_occludedLoad * priorityOf(before));
  }
}

TEST(OcclusionSelectors, LakhiaGivesAHiddenSiblingsTimeToTheVisibleOnes) {
  const Skeleton sk = test::makeSyntheticCity({});
  SelectorParams params;
  params.lakhia.c_targetTime = 8.0;  // tight: the street cannot all be refined
  View v = streetView();
  auto run = [&](const OcclusionOracle* oracle) {
    auto sel = std::move(*makeSelector("lakhia", sk, params));
    sel->setVTime(1e-4);
    v.occlusion = oracle;
    Selection s;
    for (int i = 0; i < 30; ++i) s = sel->select(v, AllResident{});  // hysteresis settles
    return s;
  };
  const Selection open = run(nullptr);
  // Hide every block but the nearest two.
  Hidden hidden;
  for (std::uint32_t r : sk.roots)
    if (sk.nodes[r].bounds.min.x > 60.0) hidden.nodes.insert(r);
  const Selection culled = run(&hidden);
  EXPECT_FALSE(culled.occluded.empty());
  std::uint64_t openNear = 0, culledNear = 0;
  for (std::uint32_t n : open.front)
    if (sk.nodes[n].bounds.min.x <= 60.0) openNear += sk.nodes[n].numTri;
  for (std::uint32_t n : culled.front) culledNear += sk.nodes[n].numTri;
  // The budget freed by the hidden blocks buys detail on the visible ones.
  EXPECT_GT(culledNear, openNear);
  EXPECT_LE(culled.estimatedMs, params.lakhia.c_targetTime * 1.3);
}

TEST(OcclusionSelectors, ANodeWhoseChildrenInViewAreAllHiddenIsNotDrawn) {
  const Skeleton sk = test::makeSyntheticCity({});
  SelectorParams params;
  params.lakhia.c_targetTime = 1e4;
  const std::uint32_t root = sk.roots[0];
  Hidden hidden;
  for (std::uint32_t c = sk.nodes[root].firstChild;
       c < sk.nodes[root].firstChild + sk.nodes[root].childCount; ++c)
    hidden.nodes.insert(c);
  for (const char* name : {"lakhia", "sse", "full"}) {
    SCOPED_TRACE(name);
    auto sel = std::move(*makeSelector(name, sk, params));
    sel->setVTime(1e-5);
    View v = streetView();
    v.occlusion = &hidden;
    const Selection s = sel->select(v, AllResident{});
    for (std::uint32_t n : s.front) EXPECT_NE(sk.nodes[n].block, sk.nodes[root].block);
    EXPECT_FALSE(s.occluded.empty());
  }
}

namespace {

struct OcclusionRig {
  OcclusionRig() : source(test::makeSyntheticCity({})), renderer(source.skeleton().nodes.size()) {
    renderer.setTriangles(source.skeleton());
    loader = std::make_unique<Loader>(source);
    SelectorParams p;
    p.lakhia.c_targetTime = 1e4;
    FrameDriverOptions o;
    o.width = 640;
    o.height = 360;
    o.loaderThread = false;
    o.occlusion = OcclusionMode::On;
    driver = std::make_unique<FrameDriver>(std::move(*makeSelector("full", source.skeleton(), p)),
                                           nullptr, *loader, renderer, o);
    EXPECT_TRUE(driver->start().ok());
    while (loader->step()) {
    }
  }
  CameraSample at(double t) const {
    CameraSample s;
    s.time = t;
    s.camera.position = {-5.0, 46.0, 1.7};
    s.camera.target = {100.0, 46.0, 5.0};
    return s;
  }
  bool drawn(std::uint32_t block) const {
    for (std::uint32_t n : driver->lastFront())
      if (source.skeleton().nodes[n].block == block) return true;
    return false;
  }
  FrameRecord frame(double t) {
    auto r = driver->renderFrame(at(t), FrameMode::Settled);
    EXPECT_TRUE(r.ok());
    return r.ok() ? *r : FrameRecord{};
  }
  test::MemoryNodeSource source;
  SimulatedRenderer renderer;
  std::unique_ptr<Loader> loader;
  std::unique_ptr<FrameDriver> driver;
};

}  // namespace

TEST(OcclusionFrames, AWallHidesBoxesFromTheSecondFrameAndTheyComeBackTheFrameAfterTheyShow) {
  OcclusionRig rig;
  const Skeleton& sk = rig.source.skeleton();
  // A wall: block 1 (second along the street) and every node of it is hidden.
  bool wall = true;
  rig.renderer.hidden = [&](std::uint32_t n) { return wall && sk.nodes[n].block == 1; };
  const FrameRecord first = rig.frame(0.0);
  EXPECT_TRUE(rig.drawn(1));  // the first frame draws everything in the frustum
  EXPECT_EQ(first.occludedNodes, 0u);
  rig.frame(1.0 / 30);
  EXPECT_FALSE(rig.drawn(1));
  const FrameRecord third = rig.frame(2.0 / 30);
  EXPECT_FALSE(rig.drawn(1));
  EXPECT_GT(third.occludedNodes, 0u);
  EXPECT_GT(third.occludedTriangles, 0u);
  EXPECT_GT(third.occlusionQueries, 0u);
  EXPECT_TRUE(third.occlusion);
  // Its boxes were queried in that frame's box pass, and no other block's.
  ASSERT_FALSE(rig.renderer.lastQueriedBoxes.empty());
  for (std::uint32_t n : rig.renderer.lastQueriedBoxes) EXPECT_EQ(sk.nodes[n].block, 1u);
  wall = false;  // it comes into view during this frame
  rig.frame(3.0 / 30);
  EXPECT_FALSE(rig.drawn(1));  // the answer arrives one frame late
  rig.frame(4.0 / 30);
  EXPECT_TRUE(rig.drawn(1));
}

TEST(OcclusionFrames, TheBoxPassIsReservedFromTheNextFramesBudget) {
  OcclusionRig rig;
  const Skeleton& sk = rig.source.skeleton();
  rig.renderer.hidden = [&](std::uint32_t n) { return sk.nodes[n].block != 0; };
  rig.renderer.msPerBoxQuery = 0.5;
  FrameRecord r;
  for (int i = 0; i < 4; ++i) r = rig.frame(i / 30.0);
  ASSERT_GT(r.occlusionMs, 0.0);
  const FrameRecord next = rig.frame(4 / 30.0);
  // estimatedMs = spent (uploads, per-pixel passes, last box pass) + the front's estimate.
  EXPECT_GE(next.estimatedMs, r.occlusionMs);
}

TEST(OcclusionFrames, ACameraJumpForgetsVisibilityAndDrawsEverythingInView) {
  OcclusionRig rig;
  const Skeleton& sk = rig.source.skeleton();
  rig.renderer.hidden = [&](std::uint32_t n) { return sk.nodes[n].block == 1; };
  for (int i = 0; i < 3; ++i) rig.frame(i / 30.0);
  ASSERT_FALSE(rig.drawn(1));
  rig.frame(5.0);  // five seconds later: another part of the path
  EXPECT_TRUE(rig.drawn(1));
}

TEST(OcclusionFrames, WithCullingOffNothingIsQueried) {
  OcclusionRig rig;
  rig.renderer.hidden = [&](std::uint32_t) { return true; };
  FrameDriverOptions o;
  o.occlusion = OcclusionMode::Off;
  o.loaderThread = false;
  FrameDriver off(std::move(*makeSelector("full", rig.source.skeleton(), {})), nullptr,
                  *rig.loader, rig.renderer, o);
  ASSERT_TRUE(off.start().ok());
  for (int i = 0; i < 3; ++i) {
    auto r = off.renderFrame(rig.at(i / 30.0), FrameMode::Settled);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->occlusionQueries, 0u);
    EXPECT_EQ(r->occludedNodes, 0u);
    EXPECT_FALSE(r->occlusion);
  }
}
