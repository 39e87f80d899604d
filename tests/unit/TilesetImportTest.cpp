// A tileset as a node store (hlod/tiles/TilesetImport.h): b3dm with RTC_CENTER, the tileset's
// errors kept, empty tiles giving their place to their children, ADD refinement handed down,
// earth-centred tilesets in an east-north-up frame, the up axis, and NASA's Mars tileset with
// its broken and external variants, case by case.
#include <gtest/gtest.h>

#include <filesystem>

#include "SharedData.h"
#include "TilesetTestUtil.h"
#include "hlod/geodesy/Geodesy.h"
#include "hlod/store/NodeStore.h"
#include "hlod/tiles/TilesetImport.h"

namespace hlod::tiles {
namespace {

namespace fs = std::filesystem;
using hlod::testing::b3dm;
using hlod::testing::squareGlb;
using hlod::testing::TempDir;
using hlod::testing::tile;
using hlod::testing::tileset;

Result<TilesetImportReport> import(const TempDir& dir, const std::string& name = "tileset.json") {
  return buildStoreFromTileset(dir.file(name), dir.file("out.hlod"));
}

TEST(TilesetImport, B3dmTilesKeepTheirTreeAndErrorsAndRtcCentresPlaceThem) {
  TempDir dir;
  // glTF y up: a square at glTF (x, z) = (0..2, 0..2) is tile (x, y) = (0..2, -2..0).
  dir.write("r.b3dm",
            b3dm(squareGlb(0, 0, 0, 2), {{"BATCH_LENGTH", 0}, {"RTC_CENTER", {100, 0, 0}}}));
  dir.write("a.b3dm", b3dm(squareGlb(0, 0, 0, 1), {{"BATCH_LENGTH", 0}}));
  dir.write("b.b3dm",
            b3dm(squareGlb(1, 1, 0, 1, nullptr, glm::vec4(1.0f), true), {{"BATCH_LENGTH", 0}}));
  dir.write("tileset.json",
            tileset(tile("r.b3dm", 6.0, {tile("a.b3dm", 0.0), tile("b.b3dm", 0.0)}), "1.0").dump());
  auto r = import(dir);
  ASSERT_TRUE(r) << r.message();
  const Skeleton& s = r->skeleton;
  ASSERT_EQ(s.nodes.size(), 3u);
  EXPECT_EQ(s.roots, std::vector<std::uint32_t>{0});
  EXPECT_EQ(s.nodes[0].childCount, 2u);
  EXPECT_EQ(s.nodes[0].geometricError, 6.0);
  EXPECT_EQ(s.nodes[1].geometricError, 0.0);
  EXPECT_EQ(s.nodes[1].level, 1u);
  // The root's square, moved by RTC_CENTER along the tile frame's x.
  EXPECT_NEAR(s.nodes[0].bounds.min.x, 100.0, 1e-9);
  EXPECT_NEAR(s.nodes[0].bounds.max.x, 102.0, 1e-9);
  EXPECT_NEAR(s.nodes[0].bounds.min.y, -2.0, 1e-9);
  EXPECT_NEAR(s.nodes[0].bounds.max.y, 0.0, 1e-9);
  EXPECT_EQ(s.nodes[0].numTri, 2u);
  EXPECT_GT(s.nodes[0].cost, 0.0);
  EXPECT_GT(s.nodes[0].staticBenefit, 0.0);
  EXPECT_EQ(s.up, UpAxis::Z);  // the squares face tile z (glTF y)
  auto store = NodeStore::open(dir.file("out.hlod"));
  ASSERT_TRUE(store) << store.message();
  auto mesh = (*store)->loadNode(1);
  ASSERT_TRUE(mesh) << mesh.message();
  EXPECT_TRUE(mesh->oneSided);  // a glTF material without doubleSided: back faces culled
  mesh = (*store)->loadNode(2);
  ASSERT_TRUE(mesh) << mesh.message();
  EXPECT_FALSE(mesh->oneSided);  // doubleSided
}

TEST(TilesetImport, TilesWithoutContentGiveTheirPlaceToTheirChildren) {
  TempDir dir;
  dir.write("a.glb", squareGlb(0, 0, 0, 1));
  dir.write("b.glb", squareGlb(2, 0, 0, 1));
  // root (empty) -> [a, mid (empty) -> [b, b]]: roots a and ... the mid tile's children.
  dir.write(
      "tileset.json",
      tileset(tile("", 9.0,
                   {tile("a.glb", 0.0), tile("", 4.0, {tile("b.glb", 0.0), tile("b.glb", 0.0)})}))
          .dump());
  auto r = import(dir);
  ASSERT_TRUE(r) << r.message();
  EXPECT_EQ(r->emptyTiles, 2u);
  EXPECT_EQ(r->skeleton.nodes.size(), 3u);
  EXPECT_EQ(r->skeleton.roots.size(), 3u);  // the empty root's and mid tile's children
}

TEST(TilesetImport, AddRefinementHandsTheParentsTrianglesDownToItsChildren) {
  TempDir dir;
  // The parent: two squares, one over each child's box; children: one square each.
  dir.write("p.glb", squareGlb(0, 0, 5, 1));
  dir.write("q.glb", squareGlb(10, 0, 5, 1));
  dir.write("a.glb", squareGlb(0, 0, 0, 1));
  dir.write("b.glb", squareGlb(10, 0, 0, 1));
  nlohmann::json a = tile("a.glb", 0.0), b = tile("b.glb", 0.0);
  a["boundingVolume"]["box"] = {0.5, -0.5, 0, 1, 0, 0, 0, 1, 0, 0, 0, 6};
  b["boundingVolume"]["box"] = {10.5, -0.5, 0, 1, 0, 0, 0, 1, 0, 0, 0, 6};
  nlohmann::json root = tile("", 2.0, {a, b});
  root["contents"] = {{{"uri", "p.glb"}}, {{"uri", "q.glb"}}};
  root["refine"] = "ADD";
  dir.write("tileset.json", tileset(root).dump());
  auto r = import(dir);
  ASSERT_TRUE(r) << r.message();
  const Skeleton& s = r->skeleton;
  ASSERT_EQ(s.nodes.size(), 3u);
  EXPECT_EQ(s.nodes[0].numTri, 4u);  // the parent drawn alone: its own triangles
  EXPECT_EQ(s.nodes[1].numTri, 4u);  // each child: its own and the parent's nearest square
  EXPECT_EQ(s.nodes[2].numTri, 4u);
  EXPECT_LT(s.nodes[1].bounds.max.x, 5.0);
  EXPECT_GT(s.nodes[2].bounds.min.x, 5.0);
  EXPECT_EQ(r->addTiles, 3u);
}

TEST(TilesetImport, AnEarthCentredTilesetComesInEastNorthUpAtItsCentre) {
  TempDir dir;
  const LatLon where{47.3769, 8.5417, 400.0};
  const EnuFrame enu(where);
  // RTC_CENTER at the place: the content is glTF y up, turned to z up around it; the tile has an
  // ENU-to-ECEF transform as Cesium's eastNorthUpToFixedFrame gives.
  const glm::dvec3 ecef = geodeticToEcef(where);
  dir.write("a.b3dm", b3dm(squareGlb(-5, -5, 0, 10), {{"BATCH_LENGTH", 0}}));
  nlohmann::json root = tile("a.b3dm", 0.0);
  const glm::dmat3 r = glm::transpose(enu.rotation());
  root["transform"] = {r[0].x, r[0].y, r[0].z, 0, r[1].x, r[1].y, r[1].z, 0,
                       r[2].x, r[2].y, r[2].z, 0, ecef.x, ecef.y, ecef.z, 1};
  dir.write("tileset.json", tileset(root).dump());
  auto rep = import(dir);
  ASSERT_TRUE(rep) << rep.message();
  const Skeleton& s = rep->skeleton;
  EXPECT_EQ(s.up, UpAxis::Z);
  EXPECT_TRUE(s.crs.toEnu);
  EXPECT_NEAR(s.crs.originLat, where.lat, 1e-6);
  EXPECT_NEAR(s.crs.originLon, where.lon, 1e-6);
  // The square lies flat around the origin, not 6,400 km away.
  EXPECT_NEAR(s.nodes[0].bounds.min.z, 0.0, 1e-6);
  EXPECT_NEAR(s.nodes[0].bounds.max.z, 0.0, 1e-6);
  EXPECT_NEAR(s.nodes[0].bounds.min.x, -5.0, 1e-6);
  EXPECT_EQ(s.quadtree.domain, QuadtreeDomain::Geographic);
}

TEST(TilesetImport, ALocalTilesetStandsOnTheAxisItsSurfacesFace) {
  TempDir dir;
  // gltfUpAxis Z: the glTF's y stays y, and the squares face y.
  dir.write("a.glb", squareGlb(0, 0, 0, 1));
  nlohmann::json t = tileset(tile("a.glb", 0.0), "1.0");
  t["asset"]["gltfUpAxis"] = "Z";
  dir.write("tileset.json", t.dump());
  auto r = import(dir);
  ASSERT_TRUE(r) << r.message();
  EXPECT_EQ(r->skeleton.up, UpAxis::Y);
  TilesetImportOptions o;
  o.up = UpAxis::Z;
  r = buildStoreFromTileset(dir.file("tileset.json"), dir.file("z.hlod"), o);
  ASSERT_TRUE(r) << r.message();
  EXPECT_EQ(r->skeleton.up, UpAxis::Z);
}

TEST(TilesetImport, ATilesetWithoutTrianglesIsAnError) {
  TempDir dir;
  dir.write("p.pnts", "pnts\x01\x00\x00\x00");
  dir.write("tileset.json", tileset(tile("p.pnts", 0.0)).dump());
  auto r = import(dir);
  ASSERT_FALSE(r);
  EXPECT_NE(r.message().find("no tile holds triangles"), std::string::npos) << r.message();
}

TEST(TilesetImport, ACorruptContentIsAnErrorNamingTheTileAndTheFile) {
  TempDir dir;
  std::string glb = squareGlb(0, 0, 0, 1);
  dir.write("a.glb", glb);
  dir.write("bad.glb", glb.substr(0, glb.size() - 40));
  dir.write("tileset.json", tileset(tile("a.glb", 1.0, {tile("bad.glb", 0.0)})).dump());
  auto r = import(dir);
  ASSERT_FALSE(r);
  EXPECT_NE(r.message().find("tile root/0: content bad.glb"), std::string::npos) << r.message();
  EXPECT_FALSE(fs::exists(dir.file("out.hlod")));
}

// NASA's Mars tileset (3DTilesRendererJS example data, 3D Tiles 1.0, b3dm, gltfUpAxis Z).
class MarsTileset : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(test::sharedData("mars-tileset/tileset.json")))
      GTEST_SKIP() << "shared data not found: " << test::sharedData("mars-tileset");
  }
  Result<TilesetImportReport> build(const std::string& name) {
    return buildStoreFromTileset(test::sharedData("mars-tileset/" + name), dir.file("mars.hlod"));
  }
  TempDir dir;
};

TEST_F(MarsTileset, TheWholeSetImportsWithItsQuadtreeAndErrors) {
  auto r = build("tileset.json");
  ASSERT_TRUE(r) << r.message();
  EXPECT_EQ(r->tiles, 293u);
  EXPECT_EQ(r->nodes, 293u);
  EXPECT_EQ(r->skeleton.roots.size(), 1u);
  EXPECT_EQ(r->skeleton.nodes[0].childCount, 4u);
  EXPECT_NEAR(r->skeleton.nodes[0].geometricError, 30.26052821016646, 1e-9);
  EXPECT_EQ(r->skeleton.up, UpAxis::Y);  // y-up terrain marked gltfUpAxis Z
  std::uint32_t depth = 0;
  for (const NodeInfo& n : r->skeleton.nodes) depth = std::max(depth, n.level + 1);
  EXPECT_EQ(depth, 5u);
}

TEST_F(MarsTileset, TheAddVariantImportsWithEveryTilesTrianglesOnceInTheLeaves) {
  auto add = build("tileset-add.json");
  ASSERT_TRUE(add) << add.message();
  EXPECT_EQ(add->addTiles, 293u);
  std::uint64_t all = 0, leaves = 0;
  for (const NodeInfo& n : add->skeleton.nodes) {
    if (n.childCount == 0) leaves += n.numTri;
  }
  auto replace =
      buildStoreFromTileset(test::sharedData("mars-tileset/tileset.json"), dir.file("r.hlod"));
  ASSERT_TRUE(replace);
  for (const NodeInfo& n : replace->skeleton.nodes) all += n.numTri;
  EXPECT_EQ(leaves, all);  // ADD: the leaves draw every tile's content
}

TEST_F(MarsTileset, ABrokenRootContentIsRefusedNamingTheTileAndTheFile) {
  auto r = build("tileset-broken-root-content.json");
  ASSERT_FALSE(r);
  EXPECT_NE(r.message().find("tile root: content 'root-non-existent.b3dm' not found"),
            std::string::npos)
      << r.message();
}

TEST_F(MarsTileset, TheExternalVariantImportsTheSameTilesThroughTheChildTileset) {
  auto r = build("tileset-external.json");
  ASSERT_TRUE(r) << r.message();
  EXPECT_EQ(r->nodes, 293u);
  EXPECT_EQ(r->emptyTiles, 1u);  // the tile that pointed to the external tileset
  auto params = build("tileset-external-with-url-params.json");
  ASSERT_TRUE(params) << params.message();
  EXPECT_EQ(params->nodes, 293u);
}

TEST_F(MarsTileset, ABrokenExternalTilesetIsRefusedNamingIt) {
  auto r = build("tileset-external-broken.json");
  ASSERT_FALSE(r);
  EXPECT_NE(r.message().find("tile root/0/0"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("nonexistent.json"), std::string::npos) << r.message();
}

TEST_F(MarsTileset, MissingContentAtTheRootOrMidTreeGivesThePlaceToTheChildren) {
  auto root = build("tileset-no-root-content.json");
  ASSERT_TRUE(root) << root.message();
  EXPECT_EQ(root->nodes, 292u);
  EXPECT_EQ(root->skeleton.roots.size(), 4u);
  auto mid = buildStoreFromTileset(test::sharedData("mars-tileset/tileset-no-midtile-content.json"),
                                   dir.file("mid.hlod"));
  ASSERT_TRUE(mid) << mid.message();
  EXPECT_EQ(mid->nodes, 292u);
  EXPECT_EQ(mid->skeleton.nodes[1].childCount, 7u);  // tile 0: three children and 01's four
}

}  // namespace
}  // namespace hlod::tiles
