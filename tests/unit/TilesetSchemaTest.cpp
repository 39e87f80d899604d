// The tileset checks written from the 3D Tiles 1.1 JSON schemas (TilesetSchemaCheck.h): one test
// per rule, each a valid tileset broken in that one place, so that each rule is known to catch
// what it names (the exporter's output is checked by them in TilesetExportTest).
#include <gtest/gtest.h>

#include "TilesetSchemaCheck.h"

namespace {

using nlohmann::json;

json validTileset() {
  return json::parse(R"({
    "asset": {"version": "1.1"},
    "geometricError": 100,
    "root": {
      "boundingVolume": {"box": [0,0,0, 10,0,0, 0,10,0, 0,0,10]},
      "geometricError": 10, "refine": "REPLACE",
      "content": {"uri": "a.glb"},
      "children": [{"boundingVolume": {"sphere": [0,0,0,5]}, "geometricError": 0,
                    "content": {"uri": "b.glb"}}]
    }})");
}

// The rules `t` breaks (no content reader: the box rule has its own test).
std::vector<std::string> brokenRules(const json& t) {
  std::vector<std::string> out;
  for (const auto& v : tilesetcheck::Checker().check(t)) out.push_back(v.rule);
  return out;
}

std::vector<std::string> onlyRule(const std::string& rule) {
  return {rule};
}

TEST(TilesetSchema, TheValidTilesetBreaksNoRule) {
  EXPECT_TRUE(brokenRules(validTileset()).empty());
}

TEST(TilesetSchema, TilesetRequiresAsset) {
  json t = validTileset();
  t.erase("asset");
  EXPECT_EQ(brokenRules(t), onlyRule("tileset.required.asset"));
}

TEST(TilesetSchema, TilesetRequiresGeometricError) {
  json t = validTileset();
  t.erase("geometricError");
  EXPECT_EQ(brokenRules(t), onlyRule("tileset.required.geometricError"));
}

TEST(TilesetSchema, TilesetRequiresRoot) {
  json t = validTileset();
  t.erase("root");
  EXPECT_EQ(brokenRules(t), onlyRule("tileset.required.root"));
}

TEST(TilesetSchema, TilesetGeometricErrorIsANumber) {
  json t = validTileset();
  t["geometricError"] = "100";
  EXPECT_EQ(brokenRules(t), onlyRule("tileset.geometricError.type"));
}

TEST(TilesetSchema, TilesetGeometricErrorIsNotNegative) {
  json t = validTileset();
  t["geometricError"] = -1;
  EXPECT_EQ(brokenRules(t), onlyRule("tileset.geometricError.minimum"));
}

TEST(TilesetSchema, AssetRequiresVersion) {
  json t = validTileset();
  t["asset"].erase("version");
  EXPECT_EQ(brokenRules(t), onlyRule("asset.required.version"));
}

TEST(TilesetSchema, AssetVersionIsAString) {
  json t = validTileset();
  t["asset"]["version"] = 1.1;
  EXPECT_EQ(brokenRules(t), onlyRule("asset.version.type"));
}

TEST(TilesetSchema, ExtensionsUsedAreUniqueStrings) {
  json t = validTileset();
  t["extensionsUsed"] = {"A", "A"};
  EXPECT_EQ(brokenRules(t), onlyRule("tileset.extensionsUsed.uniqueItems"));
  t["extensionsUsed"] = json::array();
  EXPECT_EQ(brokenRules(t), onlyRule("tileset.extensionsUsed.minItems"));
}

TEST(TilesetSchema, TileRequiresBoundingVolume) {
  json t = validTileset();
  t["root"]["children"][0].erase("boundingVolume");
  EXPECT_EQ(brokenRules(t), onlyRule("tile.required.boundingVolume"));
}

TEST(TilesetSchema, TileRequiresGeometricError) {
  json t = validTileset();
  t["root"]["children"][0].erase("geometricError");
  EXPECT_EQ(brokenRules(t), onlyRule("tile.required.geometricError"));
}

TEST(TilesetSchema, TileGeometricErrorIsNotNegative) {
  json t = validTileset();
  t["root"]["geometricError"] = -0.5;
  EXPECT_EQ(brokenRules(t), onlyRule("tile.geometricError.minimum"));
}

TEST(TilesetSchema, TileGeometricErrorIsANumber) {
  json t = validTileset();
  t["root"]["geometricError"] = json::array();
  EXPECT_EQ(brokenRules(t), onlyRule("tile.geometricError.type"));
}

TEST(TilesetSchema, RefineIsAddOrReplace) {
  json t = validTileset();
  t["root"]["refine"] = "replace-please";
  EXPECT_EQ(brokenRules(t), onlyRule("tile.refine.enum"));
}

TEST(TilesetSchema, RefineIsRequiredAtTheRoot) {
  json t = validTileset();
  t["root"].erase("refine");
  EXPECT_EQ(brokenRules(t), onlyRule("tile.refine.requiredAtRoot"));
}

TEST(TilesetSchema, TransformHasSixteenNumbers) {
  json t = validTileset();
  t["root"]["transform"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  EXPECT_EQ(brokenRules(t), onlyRule("tile.transform.items"));
}

TEST(TilesetSchema, BoxHasTwelveNumbers) {
  json t = validTileset();
  t["root"]["boundingVolume"]["box"] = {0, 0, 0, 1, 1, 1};
  EXPECT_EQ(brokenRules(t), onlyRule("boundingVolume.box.items"));
}

TEST(TilesetSchema, RegionHasSixNumbers) {
  json t = validTileset();
  t["root"]["boundingVolume"] = {{"region", {0, 0, 1, 1, 0}}};
  EXPECT_EQ(brokenRules(t), onlyRule("boundingVolume.region.items"));
}

TEST(TilesetSchema, SphereHasFourNumbers) {
  json t = validTileset();
  t["root"]["children"][0]["boundingVolume"]["sphere"] = {0, 0, "0", 5};
  EXPECT_EQ(brokenRules(t), onlyRule("boundingVolume.sphere.items"));
}

TEST(TilesetSchema, BoundingVolumeHasAProperty) {
  json t = validTileset();
  t["root"]["boundingVolume"] = json::object();
  EXPECT_EQ(brokenRules(t), onlyRule("boundingVolume.minProperties"));
}

TEST(TilesetSchema, ContentRequiresUri) {
  json t = validTileset();
  t["root"]["content"] = {{"boundingVolume", {{"sphere", {0, 0, 0, 1}}}}};
  EXPECT_EQ(brokenRules(t), onlyRule("content.required.uri"));
}

TEST(TilesetSchema, ContentUriIsAString) {
  json t = validTileset();
  t["root"]["content"]["uri"] = 7;
  EXPECT_EQ(brokenRules(t), onlyRule("content.uri.type"));
}

TEST(TilesetSchema, ContentAndContentsAreNotBoth) {
  json t = validTileset();
  t["root"]["contents"] = {{{"uri", "c.glb"}}};
  EXPECT_EQ(brokenRules(t), onlyRule("tile.contentXorContents"));
}

TEST(TilesetSchema, ContentsHasAtLeastOne) {
  json t = validTileset();
  t["root"].erase("content");
  t["root"]["contents"] = json::array();
  EXPECT_EQ(brokenRules(t), onlyRule("tile.contents.minItems"));
}

TEST(TilesetSchema, ChildrenHasAtLeastOne) {
  json t = validTileset();
  t["root"]["children"] = json::array();
  EXPECT_EQ(brokenRules(t), onlyRule("tile.children.minItems"));
}

TEST(TilesetSchema, AContentsBoxHoldsEveryVertex) {
  // The root's box spans [-10, 10]^3: a vertex at x = 10.5 lies outside, one at 9.5 inside.
  double x = 10.5;
  tilesetcheck::Checker checker([&](const std::string& uri, std::vector<glm::dvec3>& ps) {
    ps = {{0, 0, 0}, {uri == "a.glb" ? x : 0.0, 0, 0}};
    return true;
  });
  std::vector<std::string> broken;
  for (const auto& v : checker.check(validTileset())) broken.push_back(v.rule + " " + v.where);
  EXPECT_EQ(broken, onlyRule("content.box.holdsVertices /root/content"));
  x = 9.5;
  EXPECT_TRUE(checker.check(validTileset()).empty());
}

}  // namespace
