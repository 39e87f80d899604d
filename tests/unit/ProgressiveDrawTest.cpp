// Parry's hybrid drawing in the selectors (Selection::draws): a node with a progression is drawn
// with the triangles its Lakhia time slice buys, and a node that projects to a few pixels is
// drawn as its splats, each at its share of eq. 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "RuntimeTestScene.h"
#include "hlod/runtime/LakhiaSelector.h"
#include "hlod/runtime/SseSelector.h"

namespace hlod {
namespace {

using test::makeSyntheticCity;
using test::overview;
using test::SyntheticCity;

// 16 blocks of 1000 triangles at hlod_0; at 4e-3 ms per triangle hlod_0 alone is 64 ms, twice
// the 33 ms budget: only drawing fewer triangles of each node can hold it.
SyntheticCity progressiveCity() {
  SyntheticCity c;
  c.minTri = 100;
  return c;
}

SelectorParams slowMachine() {
  SelectorParams p;
  p.lakhia.vTimeInitial = 4e-3;
  return p;
}

TEST(ProgressiveDraw, AFrontOverTheBudgetAtHlod0IsDrawnWithTheTrianglesItsSlicesBuy) {
  const Skeleton sk = makeSyntheticCity(progressiveCity());
  LakhiaSelector sel(sk, slowMachine());
  const Selection s = sel.select(overview(sk), AllResident());
  ASSERT_EQ(s.draws.size(), s.front.size());
  ASSERT_FALSE(s.front.empty());
  EXPECT_EQ(s.partialNodes, s.front.size());  // every root's slice is short of its need
  std::uint64_t triangles = 0;
  for (std::size_t i = 0; i < s.front.size(); ++i) {
    const NodeInfo& n = sk.nodes[s.front[i]];
    EXPECT_FALSE(s.draws[i].splats);
    EXPECT_GE(s.draws[i].triangles, n.minTri);
    EXPECT_LT(s.draws[i].triangles, n.numTri);
    // What the slice buys, to a step of 1/32 of the node's range.
    const double bought = n.numTri * sel.timeSlice(s.front[i]) / sel.timeNeeded(s.front[i]);
    EXPECT_NEAR(s.draws[i].triangles, bought, (n.numTri - n.minTri) / 32.0);
    triangles += s.draws[i].triangles;
  }
  EXPECT_EQ(s.triangles, triangles);
  // Eq. 1 is linear in the triangles: the estimate is the budget, not twice it.
  EXPECT_NEAR(s.estimatedMs, sel.targetMs(), 0.05 * sel.targetMs());
  EXPECT_NEAR(s.estimatedCost, double(triangles), 1e-6 * triangles);
}

TEST(ProgressiveDraw, WithoutAProgressionOrWithItOffNodesAreDrawnWhole) {
  for (bool progressionInStore : {false, true}) {
    SyntheticCity c = progressiveCity();
    if (!progressionInStore) c.minTri = 0;
    const Skeleton sk = makeSyntheticCity(c);
    SelectorParams p = slowMachine();
    p.progressive = !progressionInStore;  // the store has none, or the user turned it off
    LakhiaSelector sel(sk, p);
    const Selection s = sel.select(overview(sk), AllResident());
    EXPECT_EQ(s.partialNodes, 0u);
    std::uint64_t whole = 0;
    for (std::size_t i = 0; i < s.front.size(); ++i) {
      EXPECT_EQ(s.draws[i].triangles, sk.nodes[s.front[i]].numTri);
      whole += sk.nodes[s.front[i]].numTri;
    }
    EXPECT_EQ(s.triangles, whole);
    EXPECT_GT(s.estimatedMs, 1.9 * sel.targetMs());  // hlod_0 whole: about 64 ms
  }
}

TEST(ProgressiveDraw, ABudgetThatFitsTheFrontDrawsEveryNodeWhole) {
  const Skeleton sk = makeSyntheticCity(progressiveCity());
  SelectorParams p;
  p.lakhia.vTimeInitial = 1e-6;  // the whole city fits many times over
  LakhiaSelector sel(sk, p);
  const Selection s = sel.select(overview(sk), AllResident());
  EXPECT_EQ(s.partialNodes, 0u);
  for (std::size_t i = 0; i < s.front.size(); ++i)
    EXPECT_EQ(s.draws[i].triangles, sk.nodes[s.front[i]].numTri);
}

TEST(ProgressiveDraw, NodesUnderSplatPixelsAreDrawnAsTheirSplatsAtCSplatEach) {
  SyntheticCity c;
  c.splatCount = 64;
  const Skeleton sk = makeSyntheticCity(c);
  const View v = overview(sk);
  for (double pixels : {0.0, 1e9}) {
    SelectorParams p;
    p.splats = true;
    p.splatPixels = pixels;  // none, or every node, is small enough
    SseSelector sel(sk, p);
    const Selection s = sel.select(v, AllResident());
    ASSERT_FALSE(s.front.empty());
    const bool all = pixels > 0.0;
    EXPECT_EQ(s.splatNodes, all ? s.front.size() : 0u);
    EXPECT_EQ(s.splats, all ? 64u * s.front.size() : 0u);
    EXPECT_EQ(s.triangles, all ? 0u : 1000u * s.front.size());
    const double perNode = all ? p.c_splat * 64.0 : 1000.0;
    EXPECT_NEAR(s.estimatedCost, perNode * double(s.front.size()), 1e-6);
  }
}

TEST(ProgressiveDraw, SplatsChooseTheNodesThatProjectSmallest) {
  SyntheticCity c;
  c.splatCount = 64;
  const Skeleton sk = makeSyntheticCity(c);
  // At street level the near blocks are large on screen and the far ones small.
  View v;
  v.camera.position = {-5.0, 46.0, 1.7};
  v.camera.target = {100.0, 46.0, 1.7};
  SelectorParams p;
  p.splats = true;
  p.splatPixels = 0.0;
  // splatPixels at the median size of the front on screen: about half its nodes are splats.
  std::vector<double> sizes;
  for (std::uint32_t n : SseSelector(sk, p).select(v, AllResident()).front)
    sizes.push_back(projectedPixels(v, sk.nodes[n].bounds));
  ASSERT_GT(sizes.size(), 2u);
  std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 2, sizes.end());
  p.splatPixels = sizes[sizes.size() / 2];
  SseSelector sel(sk, p);
  const Selection s = sel.select(v, AllResident());
  ASSERT_GT(s.splatNodes, 0u);
  ASSERT_LT(s.splatNodes, s.front.size());
  for (std::size_t i = 0; i < s.front.size(); ++i)
    EXPECT_EQ(s.draws[i].splats, projectedPixels(v, sk.nodes[s.front[i]].bounds) < p.splatPixels);
  // Without splats in the store nothing is drawn as splats, whatever splatPixels says.
  const Skeleton plain = makeSyntheticCity({});
  SseSelector none(plain, p);
  EXPECT_EQ(none.select(v, AllResident()).splatNodes, 0u);
}

TEST(ProgressiveDraw, SelectorParamsSetTheHybridDrawingByName) {
  SelectorParams p;
  ASSERT_TRUE(setSelectorParam(p, "splats", 1.0));
  ASSERT_TRUE(setSelectorParam(p, "splatPixels", 8.0));
  ASSERT_TRUE(setSelectorParam(p, "c_splat", 0.25));
  ASSERT_TRUE(setSelectorParam(p, "progressive", 0.0));
  EXPECT_TRUE(p.splats);
  EXPECT_EQ(p.splatPixels, 8.0);
  EXPECT_EQ(p.c_splat, 0.25);
  EXPECT_FALSE(p.progressive);
  EXPECT_FALSE(setSelectorParam(p, "splatPixels", -1.0));
  EXPECT_FALSE(setSelectorParam(p, "c_splat", std::nan("")));
}

}  // namespace
}  // namespace hlod
