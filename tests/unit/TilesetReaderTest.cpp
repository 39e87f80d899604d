// Reading a tileset's tree (hlod/tiles/TilesetReader.h): transforms, refinement, external
// tilesets, implicit quadtrees, files kept inside the folder, and errors that name the tile.
#include <gtest/gtest.h>

#include <filesystem>

#include "TilesetTestUtil.h"
#include "hlod/tiles/TilesetReader.h"

namespace hlod::tiles {
namespace {

using hlod::testing::squareGlb;
using hlod::testing::TempDir;
using hlod::testing::tile;
using hlod::testing::tileset;
namespace fs = std::filesystem;

TEST(TilesetReader, TransformsComposeDownTheTreeAndScaleTheGeometricError) {
  TempDir dir;
  dir.write("a.glb", squareGlb(0, 0, 0, 1));
  nlohmann::json child = tile("a.glb", 4.0);
  child["transform"] = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1};  // scale 2
  nlohmann::json root = tile("", 10.0, {child});
  root["transform"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 100, 200, 300, 1};  // translation
  dir.write("tileset.json", tileset(root).dump());
  auto t = readTilesetTree(dir.file("tileset.json"));
  ASSERT_TRUE(t) << t.message();
  ASSERT_EQ(t->tiles.size(), 2u);
  const TileRecord& c = t->tiles[1];
  EXPECT_EQ(c.parent, 0u);
  EXPECT_EQ(glm::dvec3(c.transform * glm::dvec4(1, 1, 1, 1)), glm::dvec3(102, 202, 302));
  EXPECT_DOUBLE_EQ(c.geometricError, 8.0);  // scaled by the largest factor
  EXPECT_EQ(c.contents.size(), 1u);
  EXPECT_EQ(c.name, "tileset.json: tile root/0");
}

TEST(TilesetReader, RefineIsInheritedAndRequiredOnlyAsAWarningAtTheRoot) {
  TempDir dir;
  dir.write("a.glb", squareGlb(0, 0, 0, 1));
  nlohmann::json grandchild = tile("a.glb", 0.0);
  nlohmann::json child = tile("a.glb", 1.0, {grandchild});
  child["refine"] = "ADD";
  nlohmann::json t = tileset(tile("a.glb", 2.0, {child}));
  dir.write("tileset.json", t.dump());
  auto r = readTilesetTree(dir.file("tileset.json"));
  ASSERT_TRUE(r) << r.message();
  EXPECT_FALSE(r->tiles[0].add);
  EXPECT_TRUE(r->tiles[1].add);
  EXPECT_TRUE(r->tiles[2].add);  // inherited
  t["root"].erase("refine");
  dir.write("tileset.json", t.dump());
  r = readTilesetTree(dir.file("tileset.json"));
  ASSERT_TRUE(r) << r.message();
  ASSERT_FALSE(r->warnings.empty());
  EXPECT_NE(r->warnings.front().find("refine"), std::string::npos);
}

TEST(TilesetReader, AnExternalTilesetHangsBelowItsTileUnderBothTransforms) {
  TempDir dir;
  fs::create_directories(dir.file("sub"));
  dir.write("sub/a.glb", squareGlb(0, 0, 0, 1));
  nlohmann::json inner = tileset(tile("a.glb", 1.0));
  inner["root"]["transform"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1};
  dir.write("sub/inner.json", inner.dump());
  nlohmann::json root = tile("sub/inner.json?v=3#x", 10.0);
  root["transform"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 7, 0, 0, 1};
  dir.write("tileset.json", tileset(root).dump());
  auto t = readTilesetTree(dir.file("tileset.json"));
  ASSERT_TRUE(t) << t.message();
  ASSERT_EQ(t->tiles.size(), 2u);
  EXPECT_TRUE(t->tiles[0].contents.empty());  // its content was the external tileset
  EXPECT_EQ(t->tiles[1].parent, 0u);
  EXPECT_EQ(glm::dvec3(t->tiles[1].transform[3]), glm::dvec3(7, 0, 5));
  ASSERT_EQ(t->tiles[1].contents.size(), 1u);
  EXPECT_EQ(t->tiles[1].contents[0].filename(), "a.glb");  // relative to sub/inner.json
}

TEST(TilesetReader, ACycleOfExternalTilesetsIsRefusedNamingTheTile) {
  TempDir dir;
  dir.write("a.json", tileset(tile("b.json", 1.0)).dump());
  dir.write("b.json", tileset(tile("", 1.0, {tile("a.json", 0.5)})).dump());
  auto t = readTilesetTree(dir.file("a.json"));
  ASSERT_FALSE(t);
  EXPECT_NE(t.message().find("cycle"), std::string::npos) << t.message();
  EXPECT_NE(t.message().find("b.json: tile root/0"), std::string::npos) << t.message();
  dir.write("self.json", tileset(tile("self.json", 1.0)).dump());
  EXPECT_NE(readTilesetTree(dir.file("self.json")).message().find("cycle"), std::string::npos);
}

TEST(TilesetReader, FilesOutsideTheTilesetsFolderAndRemoteUrlsAreRefusedByName) {
  TempDir dir;
  fs::create_directories(dir.file("set"));
  dir.write("outside.glb", squareGlb(0, 0, 0, 1));
  dir.write("set/tileset.json", tileset(tile("../outside.glb", 1.0)).dump());
  auto t = readTilesetTree(dir.file("set/tileset.json"));
  ASSERT_FALSE(t);
  EXPECT_NE(t.message().find("outside the model's folder"), std::string::npos) << t.message();
  EXPECT_NE(t.message().find("tile root"), std::string::npos) << t.message();
  dir.write("set/tileset.json", tileset(tile("https://example.org/a.glb", 1.0)).dump());
  EXPECT_NE(readTilesetTree(dir.file("set/tileset.json")).message().find("remote"),
            std::string::npos);
  dir.write("set/tileset.json", tileset(tile("/etc/passwd", 1.0)).dump());
  EXPECT_FALSE(readTilesetTree(dir.file("set/tileset.json")));
}

TEST(TilesetReader, BrokenTilesAreErrorsThatNameTheTile) {
  TempDir dir;
  dir.write("a.glb", squareGlb(0, 0, 0, 1));
  nlohmann::json bad = tile("a.glb", 1.0);
  bad.erase("geometricError");
  dir.write("tileset.json", tileset(tile("a.glb", 2.0, {tile("a.glb", 1.0), bad})).dump());
  auto t = readTilesetTree(dir.file("tileset.json"));
  ASSERT_FALSE(t);
  EXPECT_NE(t.message().find("tile root/1: geometricError"), std::string::npos) << t.message();

  dir.write("tileset.json", tileset(tile("missing.glb", 1.0)).dump());
  EXPECT_NE(readTilesetTree(dir.file("tileset.json")).message().find("not found"),
            std::string::npos);
  std::string truncated = tileset(tile("a.glb", 1.0)).dump();
  dir.write("tileset.json", truncated.substr(0, truncated.size() / 2));
  EXPECT_NE(readTilesetTree(dir.file("tileset.json")).message().find("not valid JSON"),
            std::string::npos);
  nlohmann::json both = tile("a.glb", 1.0);
  both["contents"] = {{{"uri", "a.glb"}}};
  dir.write("tileset.json", tileset(both).dump());
  EXPECT_NE(readTilesetTree(dir.file("tileset.json")).message().find("both"), std::string::npos);
}

TEST(TilesetReader, OversizedTilesetsStopAtTheLimitNamingTheTile) {
  TempDir dir;
  dir.write("a.glb", squareGlb(0, 0, 0, 1));
  std::vector<nlohmann::json> children;
  for (int i = 0; i < 20; ++i) children.push_back(tile("a.glb", 0.0));
  dir.write("tileset.json", tileset(tile("a.glb", 1.0, children)).dump());
  TilesetLimits limits;
  limits.maxTiles = 10;
  auto t = readTilesetTree(dir.file("tileset.json"), limits);
  ASSERT_FALSE(t);
  EXPECT_NE(t.message().find("more than 10 tiles"), std::string::npos) << t.message();
  EXPECT_NE(t.message().find("tile root/9"), std::string::npos) << t.message();
  // A chain deeper than the depth bound.
  nlohmann::json deep = tile("a.glb", 0.0);
  for (int i = 0; i < 8; ++i) deep = tile("a.glb", 1.0, {deep});
  dir.write("tileset.json", tileset(deep).dump());
  limits = {};
  limits.maxDepth = 5;
  EXPECT_NE(readTilesetTree(dir.file("tileset.json"), limits).message().find("levels deep"),
            std::string::npos);
}

TEST(TilesetReader, AnImplicitQuadtreeExpandsItsAvailableTilesWithHalvedErrors) {
  TempDir dir;
  fs::create_directories(dir.file("content"));
  fs::create_directories(dir.file("subtrees"));
  // Two levels in one subtree: the root and its children 0 and 3; content everywhere available.
  dir.write("subtrees/0.0.0.json",
            R"({"buffers":[{"uri":"bits.bin","byteLength":1}],
                "bufferViews":[{"buffer":0,"byteLength":1}],
                "tileAvailability":{"bitstream":0},"contentAvailability":[{"bitstream":0}],
                "childSubtreeAvailability":{"constant":0}})");
  dir.write("subtrees/bits.bin", std::string(1, char(0b10011)));
  dir.write("content/0/0/0.glb", "");
  fs::create_directories(dir.file("content/0/0"));
  fs::create_directories(dir.file("content/1/0"));
  fs::create_directories(dir.file("content/1/1"));
  dir.write("content/0/0/0.glb", squareGlb(0, 0, 0, 2));
  dir.write("content/1/0/0.glb", squareGlb(0, 0, 0, 1));
  dir.write("content/1/1/1.glb", squareGlb(1, 1, 0, 1));
  nlohmann::json root = tile("content/{level}/{x}/{y}.glb", 8.0);
  root["implicitTiling"] = {{"subdivisionScheme", "QUADTREE"},
                            {"subtreeLevels", 2},
                            {"availableLevels", 2},
                            {"subtrees", {{"uri", "subtrees/{level}.{x}.{y}.json"}}}};
  dir.write("tileset.json", tileset(root).dump());
  auto t = readTilesetTree(dir.file("tileset.json"));
  ASSERT_TRUE(t) << t.message();
  ASSERT_EQ(t->tiles.size(), 3u);
  EXPECT_EQ(t->tiles[0].children.size(), 2u);
  EXPECT_DOUBLE_EQ(t->tiles[1].geometricError, 4.0);
  ASSERT_EQ(t->tiles[0].contents.size(), 1u);
  std::set<std::string> files;
  for (std::size_t i = 1; i < 3; ++i) files.insert(t->tiles[i].contents.at(0).generic_string());
  EXPECT_TRUE(files.count(dir.file("content/1/0/0.glb").generic_string()));
  EXPECT_TRUE(files.count(dir.file("content/1/1/1.glb").generic_string()));
}

}  // namespace
}  // namespace hlod::tiles
