// The tileset checks written from the 3D Tiles 1.1 JSON schemas (TilesetSchemaCheck.h): one test
// per rule, each a valid tileset broken in that one place, so that each rule is known to catch
// what it names (the exporter's output is checked by them in TilesetExportTest).
#include <gtest/gtest.h>

#include "TilesetSchemaCheck.h"

namespace {

using nlohmann::json;

json valid() {
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
std::vector<std::string> rules(const json& t) {
  std::vector<std::string> out;
  for (const auto& v : tilesetcheck::Checker().check(t)) out.push_back(v.rule);
  return out;
}

std::vector<std::string> one(const std::string& rule) {
  return {rule};
}

TEST(TilesetSchema, TheValidTilesetBreaksNoRule) {
  EXPECT_TRUE(rules(valid()).empty());
}

TEST(TilesetSchema, TilesetRequiresAsset) {
  json t = valid();
  t.erase("asset");
  EXPECT_EQ(rules(t), one("tileset.required.asset"));
}

TEST(TilesetSchema, TilesetRequiresGeometricError) {
  json t = valid();
  t.erase("geometricError");
  EXPECT_EQ(rules(t), one("tileset.required.geometricError"));
}

TEST(TilesetSchema, TilesetRequiresRoot) {
  json t = valid();
  t.erase("root");
  EXPECT_EQ(rules(t), one("tileset.required.root"));
}

TEST(TilesetSchema, TilesetGeometricErrorIsANumber) {
  json t = valid();
  t["geometricError"] = "100";
  EXPECT_EQ(rules(t), one("tileset.geometricError.type"));
}

TEST(TilesetSchema, TilesetGeometricErrorIsNotNegative) {
  json t = valid();
  t["geometricError"] = -1;
  EXPECT_EQ(rules(t), one("tileset.geometricError.minimum"));
}

TEST(TilesetSchema, AssetRequiresVersion) {
  json t = valid();
  t["asset"].erase("version");
  EXPECT_EQ(rules(t), one("asset.required.version"));
}

TEST(TilesetSchema, AssetVersionIsAString) {
  json t = valid();
  t["asset"]["version"] = 1.1;
  EXPECT_EQ(rules(t), one("asset.version.type"));
}

TEST(TilesetSchema, ExtensionsUsedAreUniqueStrings) {
  json t = valid();
  t["extensionsUsed"] = {"A", "A"};
  EXPECT_EQ(rules(t), one("tileset.extensionsUsed.uniqueItems"));
  t["extensionsUsed"] = json::array();
  EXPECT_EQ(rules(t), one("tileset.extensionsUsed.minItems"));
}

TEST(TilesetSchema, TileRequiresBoundingVolume) {
  json t = valid();
  t["root"]["children"][0].erase("boundingVolume");
  EXPECT_EQ(rules(t), one("tile.required.boundingVolume"));
}

TEST(TilesetSchema, TileRequiresGeometricError) {
  json t = valid();
  t["root"]["children"][0].erase("geometricError");
  EXPECT_EQ(rules(t), one("tile.required.geometricError"));
}

TEST(TilesetSchema, TileGeometricErrorIsNotNegative) {
  json t = valid();
  t["root"]["geometricError"] = -0.5;
  EXPECT_EQ(rules(t), one("tile.geometricError.minimum"));
}

TEST(TilesetSchema, TileGeometricErrorIsANumber) {
  json t = valid();
  t["root"]["geometricError"] = json::array();
  EXPECT_EQ(rules(t), one("tile.geometricError.type"));
}

TEST(TilesetSchema, RefineIsAddOrReplace) {
  json t = valid();
  t["root"]["refine"] = "replace-please";
  EXPECT_EQ(rules(t), one("tile.refine.enum"));
}

TEST(TilesetSchema, RefineIsRequiredAtTheRoot) {
  json t = valid();
  t["root"].erase("refine");
  EXPECT_EQ(rules(t), one("tile.refine.requiredAtRoot"));
}

TEST(TilesetSchema, TransformHasSixteenNumbers) {
  json t = valid();
  t["root"]["transform"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  EXPECT_EQ(rules(t), one("tile.transform.items"));
}

TEST(TilesetSchema, BoxHasTwelveNumbers) {
  json t = valid();
  t["root"]["boundingVolume"]["box"] = {0, 0, 0, 1, 1, 1};
  EXPECT_EQ(rules(t), one("boundingVolume.box.items"));
}

TEST(TilesetSchema, RegionHasSixNumbers) {
  json t = valid();
  t["root"]["boundingVolume"] = {{"region", {0, 0, 1, 1, 0}}};
  EXPECT_EQ(rules(t), one("boundingVolume.region.items"));
}

TEST(TilesetSchema, SphereHasFourNumbers) {
  json t = valid();
  t["root"]["children"][0]["boundingVolume"]["sphere"] = {0, 0, "0", 5};
  EXPECT_EQ(rules(t), one("boundingVolume.sphere.items"));
}

TEST(TilesetSchema, BoundingVolumeHasAProperty) {
  json t = valid();
  t["root"]["boundingVolume"] = json::object();
  EXPECT_EQ(rules(t), one("boundingVolume.minProperties"));
}

TEST(TilesetSchema, ContentRequiresUri) {
  json t = valid();
  t["root"]["content"] = {{"boundingVolume", {{"sphere", {0, 0, 0, 1}}}}};
  EXPECT_EQ(rules(t), one("content.required.uri"));
}

TEST(TilesetSchema, ContentUriIsAString) {
  json t = valid();
  t["root"]["content"]["uri"] = 7;
  EXPECT_EQ(rules(t), one("content.uri.type"));
}

TEST(TilesetSchema, ContentAndContentsAreNotBoth) {
  json t = valid();
  t["root"]["contents"] = {{{"uri", "c.glb"}}};
  EXPECT_EQ(rules(t), one("tile.contentXorContents"));
}

TEST(TilesetSchema, ContentsHasAtLeastOne) {
  json t = valid();
  t["root"].erase("content");
  t["root"]["contents"] = json::array();
  EXPECT_EQ(rules(t), one("tile.contents.minItems"));
}

TEST(TilesetSchema, ChildrenHasAtLeastOne) {
  json t = valid();
  t["root"]["children"] = json::array();
  EXPECT_EQ(rules(t), one("tile.children.minItems"));
}

TEST(TilesetSchema, AContentsBoxHoldsEveryVertex) {
  // The root's box spans [-10, 10]^3: a vertex at x = 10.5 lies outside, one at 9.5 inside.
  double x = 10.5;
  tilesetcheck::Checker checker([&](const std::string& uri, std::vector<glm::dvec3>& ps) {
    ps = {{0, 0, 0}, {uri == "a.glb" ? x : 0.0, 0, 0}};
    return true;
  });
  std::vector<std::string> broken;
  for (const auto& v : checker.check(valid())) broken.push_back(v.rule + " " + v.where);
  EXPECT_EQ(broken, one("content.box.holdsVertices /root/content"));
  x = 9.5;
  EXPECT_TRUE(checker.check(valid()).empty());
}

}  // namespace
