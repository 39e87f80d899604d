// The Rotterdam Delfshaven CityJSON (853 buildings, EPSG:7415 = RD New + NAP) builds into many
// blocks, each anchored near 51.9 N 4.45 E through the RD New inverse projection, in one
// geographic quadtree whose smallest cells are about a block.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

#include "SharedData.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/import/Import.h"
#include "hlod/store/NodeStore.h"

using namespace hlod;
namespace fs = std::filesystem;

namespace {
const char* const kRotterdam = "rotterdam-delfshaven.cityjson.json";
}

TEST(RotterdamBlocks, BuildingsGroupWholeIntoBlocksOfTheGrid) {
  SKIP_IF_SHARED_ABSENT(kRotterdam);
  auto m = importModel(test::sharedData(kRotterdam));
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->crs.epsg, 7415);
  EXPECT_EQ(m->cityObjects, 853u);
  const auto blocks = groupBuildingsIntoBlocks(*m, 100.0);
  std::size_t buildings = 0, triangles = 0;
  for (const BuildingBlock& b : blocks) {
    buildings += b.buildings;
    triangles += b.model.triangleCount();
  }
  EXPECT_EQ(buildings, 853u);
  EXPECT_EQ(triangles, m->triangleCount());
  EXPECT_GT(blocks.size(), 20u);
  EXPECT_LT(groupBuildingsIntoBlocks(*m, 200.0).size(), blocks.size());
}

TEST(RotterdamBlocks, TheStoreAnchorsItsBlocksNearFiftyTwoNorthFourAndAHalfEast) {
  SKIP_IF_SHARED_ABSENT(kRotterdam);
  auto m = importModel(test::sharedData(kRotterdam));
  ASSERT_TRUE(m.ok()) << m.message();
  const fs::path dir =
      fs::temp_directory_path() / ("hlodr-rotterdam-" + std::to_string(::getpid()) + ".hlod");
  BuildOptions options;
  options.threads = 2;
  auto built = buildStoreFromModel(*m, dir, options);
  ASSERT_TRUE(built.ok()) << built.message();
  auto store = NodeStore::open(dir);
  ASSERT_TRUE(store.ok()) << store.message();
  const Skeleton& s = (*store)->skeleton();
  const BlockQuadtree& q = s.quadtree;
  EXPECT_EQ(q.domain, QuadtreeDomain::Geographic);
  EXPECT_EQ(q.blocks.size(), s.roots.size());
  const QuadtreeStats st = quadtreeStats(q);
  EXPECT_GT(st.blocks, 20u);
  EXPECT_GT(st.leafCells, 10u);
  for (const QuadBlock& b : q.blocks) {
    EXPECT_NEAR(b.anchor.y, 51.91, 0.05);
    EXPECT_NEAR(b.anchor.x, 4.45, 0.05);
  }
  // Cells about a 100 m block: 17 or 18 levels (76 m or 153 m north-south).
  EXPECT_GE(q.depth, 17u);
  EXPECT_LE(q.depth, 18u);
  // The model stays in RD coordinates; the anchors are where its blocks are.
  EXPECT_EQ(s.crs.epsg, 7415);
  std::error_code ec;
  fs::remove_all(dir, ec);
}
