// The global quadtree of city blocks (Parry sec. 3) on hand-built blocks: each block in the
// leaf cell that holds its latitude/longitude, across the antimeridian and at the poles; the
// depth rule; every root once; and the builder's choice of depth and domain.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <vector>

#include "hlod/builder/HlodBuilder.h"
#include "hlod/city/BlockQuadtree.h"

using namespace hlod;

namespace {

Aabb boxAt(double x, double y, double side = 100.0) {
  Aabb b;
  b.extend(glm::dvec3(x, y, 0.0));
  b.extend(glm::dvec3(x + side, y + side, 30.0));
  return b;
}

// The leaf cell that lists `root`, or nullptr.
const QuadCell* leafOf(const BlockQuadtree& t, std::uint32_t root) {
  for (const QuadCell& c : t.cells)
    for (std::uint32_t k = c.firstBlock; k < c.firstBlock + c.blockCount; ++k)
      if (t.blocks[k].root == root) return &c;
  return nullptr;
}

bool inside(const QuadRect& r, const glm::dvec2& a) {
  return a.x >= r.minU && a.x <= r.maxU && a.y >= r.minV && a.y <= r.maxV;
}

}  // namespace

TEST(BlockQuadtree, ABlockGoesIntoTheLeafCellHoldingItsAnchor) {
  const std::vector<QuadBlockInput> blocks = {
      {0, {4.45, 51.91}, boxAt(0, 0)},      {1, {4.4512, 51.9105}, boxAt(100, 0)},
      {2, {-122.27, 37.87}, boxAt(5e5, 0)}, {3, {151.21, -33.86}, boxAt(9e5, 0)},
      {4, {0.0, 0.0}, boxAt(-9e5, 0)},
  };
  const BlockQuadtree t = buildBlockQuadtree(QuadtreeDomain::Geographic, kWholeGlobe, 18, blocks);
  ASSERT_EQ(t.blocks.size(), blocks.size());
  for (const QuadBlockInput& b : blocks) {
    const QuadCell* leaf = leafOf(t, b.root);
    ASSERT_NE(leaf, nullptr) << b.root;
    EXPECT_EQ(leaf->level, 18u);
    EXPECT_TRUE(inside(quadCellRect(kWholeGlobe, leaf->level, leaf->x, leaf->y), b.anchor))
        << b.root;
    // The cell's box holds its block's box.
    EXPECT_LE(leaf->bounds.min.x, b.bounds.min.x);
    EXPECT_GE(leaf->bounds.max.x, b.bounds.max.x);
  }
  // The root is the whole globe, and its box holds every block.
  EXPECT_EQ(t.cells[0].level, 0u);
  EXPECT_EQ(t.cells[0].bounds.min.x, -9e5);
  EXPECT_EQ(t.cells[0].bounds.max.x, 9e5 + 100.0);
  // Two blocks 100 m apart in Rotterdam share few cells up the tree but not the far ones.
  EXPECT_NE(leafOf(t, 0), leafOf(t, 2));
}

TEST(BlockQuadtree, EachCellIsOneQuadrantOfItsParentAndEveryBlockIsListedOnce) {
  std::vector<QuadBlockInput> blocks;
  for (std::uint32_t i = 0; i < 200; ++i)
    blocks.push_back({i, {-179.9 + 1.8 * i, -89.0 + 0.89 * i}, boxAt(i * 200.0, 0)});
  const BlockQuadtree t = buildBlockQuadtree(QuadtreeDomain::Geographic, kWholeGlobe, 12, blocks);
  std::set<std::uint32_t> roots;
  for (const QuadBlock& b : t.blocks) roots.insert(b.root);
  EXPECT_EQ(roots.size(), blocks.size());
  for (std::size_t i = 0; i < t.cells.size(); ++i) {
    const QuadCell& c = t.cells[i];
    EXPECT_LE(c.childCount, 4u);
    EXPECT_TRUE(c.childCount == 0 || c.blockCount == 0) << "cell " << i;
    for (std::uint32_t k = c.firstChild; k < c.firstChild + c.childCount; ++k) {
      EXPECT_GT(k, i);
      EXPECT_EQ(t.cells[k].level, c.level + 1);
      EXPECT_EQ(t.cells[k].x / 2, c.x);
      EXPECT_EQ(t.cells[k].y / 2, c.y);
    }
    if (c.childCount == 0) {
      EXPECT_EQ(c.level, 12u);
    }
  }
}

TEST(BlockQuadtree, BlocksEitherSideOfTheAntimeridianGoToTheTwoEndsOfTheGlobe) {
  const std::vector<QuadBlockInput> blocks = {
      {0, {179.9995, -16.5}, boxAt(0, 0)},  // just west of the antimeridian (Fiji)
      {1, {-179.9995, -16.5}, boxAt(100, 0)},
      {2, {180.0, -16.5}, boxAt(200, 0)},           // longitude 180 is -180
      {3, {540.0 - 0.0005, -16.5}, boxAt(300, 0)},  // wraps to 179.9995
  };
  const BlockQuadtree t = buildBlockQuadtree(QuadtreeDomain::Geographic, kWholeGlobe, 18, blocks);
  const std::uint32_t last = (1u << 18) - 1;
  EXPECT_EQ(leafOf(t, 0)->x, last);
  EXPECT_EQ(leafOf(t, 1)->x, 0u);
  EXPECT_EQ(leafOf(t, 2)->x, 0u);
  EXPECT_EQ(leafOf(t, 3), leafOf(t, 0));
  for (const QuadBlock& b : t.blocks) {
    EXPECT_GE(b.anchor.x, -180.0);
    EXPECT_LT(b.anchor.x, 180.0);
  }
  EXPECT_DOUBLE_EQ(wrapLongitude(180.0), -180.0);
  EXPECT_DOUBLE_EQ(wrapLongitude(-190.0), 170.0);
}

TEST(BlockQuadtree, BlocksAtThePolesGoToTheFirstAndLastRows) {
  const std::vector<QuadBlockInput> blocks = {
      {0, {0.0, 90.0}, boxAt(0, 0)},
      {1, {-45.0, 89.99999}, boxAt(100, 0)},
      {2, {120.0, -90.0}, boxAt(200, 0)},
      {3, {-166.0, -77.85}, boxAt(300, 0)},  // McMurdo
  };
  const BlockQuadtree t = buildBlockQuadtree(QuadtreeDomain::Geographic, kWholeGlobe, 18, blocks);
  const std::uint32_t last = (1u << 18) - 1;
  EXPECT_EQ(leafOf(t, 0)->y, last);
  EXPECT_EQ(leafOf(t, 1)->y, last);
  EXPECT_EQ(leafOf(t, 2)->y, 0u);
  for (const QuadBlockInput& b : blocks) {
    const QuadCell* leaf = leafOf(t, b.root);
    EXPECT_TRUE(inside(quadCellRect(kWholeGlobe, 18, leaf->x, leaf->y), b.anchor)) << b.root;
  }
}

TEST(BlockQuadtree, TheSmallestCellIsAboutABlock) {
  // round(log2(half meridian / block)): 100 m blocks give 76 m cells north-south.
  EXPECT_EQ(quadtreeDepthFor(kHalfMeridianMetres, 100.0), 18u);
  EXPECT_EQ(quadtreeDepthFor(kHalfMeridianMetres, 200.0), 17u);
  EXPECT_EQ(quadtreeDepthFor(kHalfMeridianMetres, 1e7), 1u);
  EXPECT_EQ(quadtreeDepthFor(kHalfMeridianMetres, 1e-6), kMaxQuadtreeDepth);
  EXPECT_EQ(quadtreeDepthFor(kHalfMeridianMetres, 0.0), 0u);
  for (double block : {60.0, 100.0, 150.0, 400.0}) {
    const double side =
        kHalfMeridianMetres / std::ldexp(1.0, int(quadtreeDepthFor(kHalfMeridianMetres, block)));
    EXPECT_GE(side, block / std::sqrt(2.0) - 1e-9) << block;
    EXPECT_LE(side, block * std::sqrt(2.0) + 1e-9) << block;
  }
}

TEST(BlockQuadtree, StatsCountBlocksPerLeafAndTheCellSizeInMetres) {
  // Two blocks of three roots each (split by colour) in one cell, one block in another.
  std::vector<QuadBlockInput> blocks;
  for (std::uint32_t r = 0; r < 3; ++r) blocks.push_back({r, {4.45, 51.91}, boxAt(0, 0)});
  for (std::uint32_t r = 3; r < 6; ++r) blocks.push_back({r, {4.45001, 51.91001}, boxAt(0, 0)});
  blocks.push_back({6, {4.47, 51.92}, boxAt(0, 0)});
  const QuadtreeStats st =
      quadtreeStats(buildBlockQuadtree(QuadtreeDomain::Geographic, kWholeGlobe, 18, blocks));
  EXPECT_EQ(st.leafCells, 2u);
  EXPECT_EQ(st.blocks, 3u);
  EXPECT_EQ(st.maxBlocks, 2u);
  EXPECT_EQ(st.maxRoots, 6u);
  EXPECT_DOUBLE_EQ(st.meanBlocks, 1.5);
  EXPECT_NEAR(st.leafMetres.y, 76.3, 0.5);
  EXPECT_NEAR(st.leafMetres.x, 94.4, 0.5);  // 0.00137 degrees of longitude at 51.9 N
  EXPECT_DOUBLE_EQ(st.anchors.minV, 51.91);
  EXPECT_DOUBLE_EQ(st.anchors.maxU, 4.47);
}

TEST(BlockQuadtree, ABuiltSkeletonWithAnchorsGetsAGeographicTreeOfTheMedianBlocksSize) {
  Skeleton s;
  std::vector<std::optional<LatLon>> anchors;
  for (std::uint32_t i = 0; i < 9; ++i) {
    NodeInfo n;
    n.parent = kNoNode;
    n.bounds = boxAt(i * 250.0, 0.0, i == 8 ? 5000.0 : 200.0);  // one huge block: not the median
    s.roots.push_back(i);
    s.nodes.push_back(n);
    anchors.push_back(LatLon{51.9, 4.45 + i * 0.004, 0.0});
  }
  const BlockQuadtree t = quadtreeOfRoots(s, anchors);
  EXPECT_EQ(t.domain, QuadtreeDomain::Geographic);
  EXPECT_EQ(t.rect, kWholeGlobe);
  EXPECT_EQ(t.depth, quadtreeDepthFor(kHalfMeridianMetres, 200.0));
  EXPECT_EQ(t.blocks.size(), 9u);
  // One root without an anchor: the model's own x/y instead, a square around the box centres.
  anchors[3].reset();
  const BlockQuadtree m = quadtreeOfRoots(s, anchors);
  EXPECT_EQ(m.domain, QuadtreeDomain::Model);
  EXPECT_DOUBLE_EQ(m.rect.maxU - m.rect.minU, m.rect.maxV - m.rect.minV);
  EXPECT_EQ(m.blocks.size(), 9u);
  for (const QuadBlock& b : m.blocks) EXPECT_TRUE(inside(m.rect, b.anchor));
}

TEST(BlockQuadtree, TheSquareAroundALoneBlockFarFromTheOriginHasAWidth) {
  // lo + 1 == lo at 1e38: a square of no width gave 0/0 cell indices (the tileset fuzzer).
  const std::vector<QuadBlockInput> blocks = {{0, {1e38, -1e38}, {}}};
  const QuadRect r = squareAround(blocks);
  EXPECT_GT(r.maxU, r.minU);
  EXPECT_GT(r.maxV, r.minV);
  const BlockQuadtree t = buildBlockQuadtree(QuadtreeDomain::Model, r, 3, blocks);
  EXPECT_EQ(t.blocks.size(), 1u);
}

TEST(BlockQuadtree, TheSquareAroundAnchorsFarFromTheOriginHoldsThemAll) {
  // lo + (hi - lo) rounds below hi here: a tileset the fuzzer made had these two anchors, and the
  // store's codec refused the quadtree it wrote.
  const std::vector<QuadBlockInput> blocks = {{0, {0.5, 0.5}, {}},
                                              {1, {0.5, -9.378831972535963e24}, {}}};
  const QuadRect r = squareAround(blocks);
  for (const QuadBlockInput& b : blocks) {
    EXPECT_GE(b.anchor.x, r.minU);
    EXPECT_LE(b.anchor.x, r.maxU);
    EXPECT_GE(b.anchor.y, r.minV);
    EXPECT_LE(b.anchor.y, r.maxV);
  }
  // An infinite anchor does not make it loop: the rectangle is then simply not finite.
  const std::vector<QuadBlockInput> endless = {
      {0, {0.0, 0.0}, {}}, {1, {0.0, -std::numeric_limits<double>::infinity()}, {}}};
  EXPECT_FALSE(std::isfinite(squareAround(endless).maxV - squareAround(endless).minV));
}
