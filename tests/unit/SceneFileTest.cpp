// Scene files: one boundary that validates them (errors name the field, unknown effects list the
// known ones), effects off unless declared, fog's density and cull distance; and fog culling in
// the selectors: a node wholly beyond the cull distance never enters the front.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "RuntimeTestScene.h"
#include "hlod/runtime/FullSelector.h"
#include "hlod/runtime/LakhiaSelector.h"
#include "hlod/scene/SceneFile.h"

namespace hlod {
namespace {

TEST(SceneFile, AnEmptySceneDeclaresNoEffect) {
  auto s = parseScene("{}");
  ASSERT_TRUE(s) << s.message();
  EXPECT_FALSE(s->effects.textures);
  EXPECT_EQ(s->effects.shading, Shading::Unlit);
  EXPECT_FALSE(s->effects.sun || s->effects.fog || s->effects.shadows || s->effects.ssao ||
               s->effects.outline);
  EXPECT_FALSE(s->effects.background.sky);
}

TEST(SceneFile, ReadsEveryDeclaredEffectWithItsSettings) {
  auto s = parseScene(R"({"store": "city.hlod",
    "camera": {"position": [1, 2, 3], "target": [4, 5, 6], "fov": 40},
    "background": {"sky": {"horizon": [0.8, 0.9, 1], "zenith": [0.2, 0.4, 0.8]}},
    "effects": {"textures": true, "shading": "blinn-phong",
                "sun": {"direction": [0, 0, 2], "intensity": 1.5},
                "fog": {"density": 0.002}, "shadows": {"resolution": 1024},
                "ssao": {"radius": 1.5, "samples": 8}, "outline": true}})");
  ASSERT_TRUE(s) << s.message();
  EXPECT_EQ(s->store, "city.hlod");
  ASSERT_TRUE(s->camera);
  EXPECT_EQ(s->camera->fov, 40.0);
  EXPECT_TRUE(s->effects.background.sky);
  EXPECT_FLOAT_EQ(s->effects.background.zenith.b, 0.8f);
  EXPECT_TRUE(s->effects.textures);
  EXPECT_EQ(s->effects.shading, Shading::BlinnPhong);
  ASSERT_TRUE(s->effects.sun);
  EXPECT_DOUBLE_EQ(s->effects.sun->direction.z, 1.0);  // normalised
  EXPECT_FLOAT_EQ(s->effects.sun->intensity, 1.5f);
  EXPECT_DOUBLE_EQ(s->effects.fog->density, 0.002);
  EXPECT_EQ(s->effects.shadows->resolution, 1024);
  EXPECT_EQ(s->effects.ssao->samples, 8);
  EXPECT_TRUE(s->effects.outline);
}

// Found by the scene_file fuzz target: the default direction was 0.1% short of unit length,
// which SunLight promises (its corpus input seed-booleans.json declares "sun": true).
TEST(SceneFile, TheDefaultSunDirectionIsUnitLength) {
  auto s = parseScene(R"({"effects": {"sun": true}})");
  ASSERT_TRUE(s) << s.message();
  ASSERT_TRUE(s->effects.sun);
  EXPECT_NEAR(glm::length(s->effects.sun->direction), 1.0, 1e-12);
  EXPECT_NEAR(glm::length(defaultEffects().sun->direction), 1.0, 1e-12);
}

TEST(SceneFile, AnUnknownEffectIsAnErrorListingTheKnownOnes) {
  auto s = parseScene(R"({"effects": {"bloom": true}})");
  ASSERT_FALSE(s);
  EXPECT_EQ(s.message(),
            "effects.bloom: unknown effect (known: textures, shading, sun, fog, shadows, ssao, "
            "outline)");
}

TEST(SceneFile, SchemaErrorsNameTheField) {
  auto check = [](const char* text, const std::string& expected) {
    auto s = parseScene(text);
    ASSERT_FALSE(s) << text;
    EXPECT_EQ(s.message(), expected) << text;
  };
  check(R"({"effects": {"fog": {"density": -1}}})",
        "effects.fog.density: must be a number in 0..1 (got -1)");
  check(R"({"effects": {"shading": "phong"}})",
        "effects.shading: must be one of unlit, lambert, blinn-phong");
  check(R"({"effects": {"shadows": {"resolution": 100}, "sun": true, "shading": "lambert"}})",
        "effects.shadows.resolution: must be an integer in 256..8192 (got 100)");
  check(R"({"effects": {"shadows": true, "shading": "lambert"}})",
        "effects.shadows: needs a \"sun\"");
  check(R"({"background": {"colour": [2, 0, 0]}})",
        "background.colour: must be an array of 3 numbers in 0..1");
  check(R"({"camera": {"position": [0, 0, 0], "target": [0, 0, 0]}})",
        "camera: position and target must differ");
  check(R"({"effects": {"ssao": {"radius": 1, "smaples": 8}}})",
        "effects.ssao.smaples: unknown field (known: radius, samples, strength)");
  check(R"({"lights": []})", "lights: unknown field (known: store, camera, background, effects)");
  check("[1, 2", "not valid JSON");
}

TEST(SceneFile, EffectsDeclaredFalseStayOff) {
  auto s = parseScene(R"({"effects": {"fog": false, "ssao": false, "textures": false}})");
  ASSERT_TRUE(s) << s.message();
  EXPECT_FALSE(s->effects.fog);
  EXPECT_FALSE(s->effects.ssao);
}

TEST(SceneFile, FogDensityZeroIsDerivedFromTheFarDistance) {
  EXPECT_DOUBLE_EQ(fogDensityFor(FogEffect{0.0}, 500.0), 1.0 / 500.0);
  EXPECT_DOUBLE_EQ(fogDensityFor(FogEffect{0.01}, 500.0), 0.01);
  // Beyond the cull distance less than half an 8-bit step of the surface is left.
  const double d = fogCullDistance(0.01);
  EXPECT_LT(std::exp(-0.01 * d) * 255.0, 0.5 + 1e-9);
  EXPECT_GT(std::exp(-0.01 * d * 0.99) * 255.0, 0.5);
  EXPECT_TRUE(std::isinf(fogCullDistance(0.0)));
}

TEST(FogCulling, NodesWhollyBeyondTheFogCullDistanceLeaveTheFront) {
  test::SyntheticCity c;
  c.blocksX = 8;
  c.blocksY = 1;
  const Skeleton sk = test::makeSyntheticCity(c);
  const AllResident all;
  View v;
  // At the west end of the row of blocks, looking east along it.
  v.camera.position = {-20.0, c.blockSize * 0.5, 10.0};
  v.camera.target = {1000.0, c.blockSize * 0.5, 0.0};
  FullSelector full(sk, {});
  const Selection clear = full.select(v, all);
  EXPECT_EQ(clear.fogCulled, 0u);
  double farthest = 0.0;
  for (std::uint32_t n : clear.front)
    farthest = std::max(farthest, distanceToBox(v.camera.position, sk.nodes[n].bounds));
  ASSERT_GT(farthest, 200.0);

  v.fogCullDistance = 150.0;
  const Selection fogged = full.select(v, all);
  EXPECT_GT(fogged.fogCulled, 0u);
  EXPECT_LT(fogged.front.size(), clear.front.size());
  for (std::uint32_t n : fogged.front)
    EXPECT_LE(distanceToBox(v.camera.position, sk.nodes[n].bounds), 150.0) << "node " << n;
  // Everything the fog does not hide is still drawn.
  for (std::uint32_t n : clear.front) {
    if (distanceToBox(v.camera.position, sk.nodes[n].bounds) <= 150.0) {
      EXPECT_NE(std::find(fogged.front.begin(), fogged.front.end(), n), fogged.front.end());
    }
  }
}

}  // namespace
}  // namespace hlod
