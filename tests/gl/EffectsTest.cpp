// Effects only where the scene declares them: an undeclared effect creates no GL object and
// runs no pass; each declared one changes the image as it should: golden images with a tolerance
// (tests/data/golden/effects_*.png, rewritten with HLODR_UPDATE_GOLDEN=1), and image-property
// assertions on small hand-built scenes that say why (fog brightens far pixels towards the fog
// colour, a shadow darkens the ground behind an occluder, SSAO darkens a crease, the outline
// darkens silhouettes).
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "GlTestScene.h"
#include "hlod/import/Import.h"
#include "renderer/FrameView.h"
#include "renderer/GpuMesh.h"

using namespace gltest;
using renderer::Pass;

namespace {

constexpr int kW = 200, kH = 150;

std::unique_ptr<renderer::GlContext> context() {
  auto c = renderer::createContext(renderer::Backend::Auto);
  if (!c) return nullptr;
  return std::move(*c);
}

// Bare effects: unlit, no textures, flat background; tests add one effect at a time.
hlod::SceneEffects bare() {
  return hlod::SceneEffects{};
}

hlod::SceneEffects litWithSun() {
  hlod::SceneEffects e;
  e.shading = hlod::Shading::Lambert;
  e.sun = hlod::SunLight{};
  e.sun->direction = glm::normalize(glm::dvec3(1.0, 0.2, 0.6));
  return e;
}

struct Shot {
  hlod::Image image;
  renderer::FrameTiming timing;
  std::vector<Pass> passes;
  renderer::ResourceCounts resources;
  renderer::FrameView view;
  int compilesBefore = 0, compilesAfter = 0;
};

// A ground quad and a box standing on it at the origin, seen from above and to the side.
std::vector<hlod::Mesh> boxOnGround() {
  return {quad(-30, -30, 30, 30, 0, {0.8f, 0.8f, 0.8f, 1}),
          box({0, 0, 2}, {1, 1, 2}, {0.8f, 0.5f, 0.3f, 1})};
}

Shot render(renderer::GlContext& ctx, const hlod::SceneEffects& effects,
            const std::vector<hlod::Mesh>& meshes, glm::dvec3 eye = {0, -14, 9},
            glm::dvec3 target = {0, 0, 0}, int frames = 1) {
  renderer::RenderOptions options;
  options.width = kW;
  options.height = kH;
  options.effects = effects;
  auto r = renderer::Renderer::create(ctx, options);
  EXPECT_TRUE(r) << (r ? "" : r.message());
  Shot s;
  if (!r) return s;
  std::vector<renderer::GpuMesh> gpu;
  for (const auto& m : meshes)
    gpu.push_back(std::move(*renderer::GpuMesh::upload(ctx.gl(), hlod::toLocal(m))));
  std::vector<const renderer::GpuMesh*> list;
  for (const auto& g : gpu) list.push_back(&g);
  s.view = renderer::makeFrameView(eye, target, {0, 0, 1}, 50.0, double(kW) / kH, 0.1, 200.0);
  s.view.sceneCentre = {0, 0, 2};
  s.view.sceneRadius = 12.0;
  s.compilesBefore = (*r)->programCompiles();
  for (int i = 0; i < frames; ++i) s.timing = (*r)->drawFrame(s.view, list);
  s.compilesAfter = (*r)->programCompiles();
  s.image = (*r)->readback();
  // HLODR_EFFECTS_DUMP=DIR keeps every frame, to look at.
  if (const char* dir = std::getenv("HLODR_EFFECTS_DUMP")) {
    static int n = 0;
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    (void)renderer::writeImage(
        std::string(dir) + "/" + test->name() + "_" + std::to_string(n++) + ".png", s.image);
  }
  s.passes = (*r)->passes();
  s.resources = (*r)->resources();
  return s;
}

// The pixel (x right, y down) where a world point lands.
glm::ivec2 project(const renderer::FrameView& v, const glm::dvec3& p) {
  const glm::dvec4 clip = v.projection * v.rotation * glm::dvec4(p - v.eye, 1.0);
  const glm::dvec2 ndc(clip.x / clip.w, clip.y / clip.w);
  return {static_cast<int>((ndc.x * 0.5 + 0.5) * kW), static_cast<int>((0.5 - ndc.y * 0.5) * kH)};
}

double luminance(const hlod::Image& img, glm::ivec2 p) {
  // A 3x3 mean: robust to one-pixel edges of rasterisation.
  double sum = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const glm::ivec4 c = pixel(img, p.x + dx, p.y + dy);
      sum += 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
    }
  return sum / 9.0;
}

std::vector<std::string> names(const std::vector<Pass>& passes) {
  std::vector<std::string> out;
  for (Pass p : passes) out.push_back(renderer::passName(p));
  return out;
}

}  // namespace

TEST(Effects, BareSceneRunsOnlyTheGeometryPassWithOneProgramAndNoTextures) {
  auto ctx = context();
  if (!ctx) GTEST_SKIP() << "no GL context";
  const Shot s = render(*ctx, bare(), boxOnGround());
  EXPECT_EQ(names(s.passes), std::vector<std::string>{"geometry"});
  renderer::ResourceCounts expected;
  expected.framebuffers = 1;   // the frame's
  expected.renderbuffers = 2;  // colour and depth
  expected.programs = 1;       // the untextured unlit mesh variant
  expected.queries = 1;        // the geometry pass's timer
  EXPECT_EQ(s.resources, expected);
  ASSERT_EQ(s.timing.passes.size(), 1u);
  EXPECT_EQ(s.timing.passes[0].name, "geometry");
}

TEST(Effects, EachUndeclaredEffectAddsNothingAndEachDeclaredOneOnlyItsOwn) {
  auto ctx = context();
  if (!ctx) GTEST_SKIP() << "no GL context";
  const auto base = render(*ctx, litWithSun(), boxOnGround()).resources;
  // Fog and textures are shader variants: no resources, no pass.
  auto fog = litWithSun();
  fog.fog = hlod::FogEffect{0.05};
  const Shot f = render(*ctx, fog, boxOnGround());
  EXPECT_EQ(f.resources, base);
  EXPECT_EQ(names(f.passes), std::vector<std::string>{"geometry"});

  auto shadows = litWithSun();
  shadows.shadows = hlod::ShadowEffect{512};
  const Shot sh = render(*ctx, shadows, boxOnGround());
  EXPECT_EQ(names(sh.passes), (std::vector<std::string>{"shadow", "geometry"}));
  EXPECT_EQ(sh.resources.framebuffers, base.framebuffers + 1);
  EXPECT_EQ(sh.resources.textures, base.textures + 1);  // the shadow map
  EXPECT_EQ(sh.resources.programs, base.programs + 1);  // the depth-only program
  EXPECT_EQ(sh.resources.queries, 2);

  auto ssao = litWithSun();
  ssao.ssao = hlod::SsaoEffect{};
  const Shot ao = render(*ctx, ssao, boxOnGround());
  EXPECT_EQ(names(ao.passes),
            (std::vector<std::string>{"geometry", "ssao", "ssao-blur", "composite"}));
  // Depth becomes a texture (a renderbuffer less), plus the occlusion and blurred targets.
  EXPECT_EQ(ao.resources.renderbuffers, base.renderbuffers - 1);
  EXPECT_EQ(ao.resources.textures, base.textures + 3);
  EXPECT_EQ(ao.resources.framebuffers, base.framebuffers + 3);
  EXPECT_EQ(ao.resources.programs, base.programs + 3);

  auto sky = litWithSun();
  sky.background.sky = true;
  const Shot sk = render(*ctx, sky, boxOnGround());
  EXPECT_EQ(names(sk.passes), (std::vector<std::string>{"geometry", "sky"}));
  EXPECT_EQ(sk.resources.textures, base.textures);
  EXPECT_EQ(sk.resources.framebuffers, base.framebuffers);

  auto all = litWithSun();
  all.fog = hlod::FogEffect{};
  all.shadows = hlod::ShadowEffect{512};
  all.ssao = hlod::SsaoEffect{};
  all.outline = hlod::OutlineEffect{};
  all.background.sky = true;
  const Shot a = render(*ctx, all, boxOnGround());
  EXPECT_EQ(names(a.passes), (std::vector<std::string>{"shadow", "geometry", "sky", "ssao",
                                                       "ssao-blur", "composite", "outline"}));
  ASSERT_EQ(a.timing.passes.size(), a.passes.size());
  for (std::size_t i = 0; i < a.passes.size(); ++i)
    EXPECT_EQ(a.timing.passes[i].name, renderer::passName(a.passes[i]));
}

// Each effect added to the one before it, on a textured box on a ground: every frame is its
// golden image within a tolerance, and differs from the frame before (the effect did something).
TEST(Effects, EachEffectAddedInTurnDrawsItsGoldenImage) {
  auto ctx = context();
  if (!ctx) GTEST_SKIP() << "no GL context";
  auto meshes = boxOnGround();
  meshes[1].texture = checker();
  meshes.push_back(box({4, 3, 1}, {1.5, 1, 1}, {0.3f, 0.5f, 0.8f, 1}));
  struct Step {
    const char* name;
    void (*add)(hlod::SceneEffects&);
  };
  const Step steps[] = {
      {"unlit", [](hlod::SceneEffects&) {}},
      {"textures", [](hlod::SceneEffects& e) { e.textures = true; }},
      {"lambert",
       [](hlod::SceneEffects& e) {
         // From behind and above the boxes: the ground in front of them catches the highlight
         // and their shadows fall towards the camera.
         e.shading = hlod::Shading::Lambert;
         e.sun = hlod::SunLight{};
         e.sun->direction = glm::normalize(glm::dvec3(0.3, 0.8, 0.5));
       }},
      {"blinn_phong", [](hlod::SceneEffects& e) { e.shading = hlod::Shading::BlinnPhong; }},
      {"sky", [](hlod::SceneEffects& e) { e.background.sky = true; }},
      {"fog", [](hlod::SceneEffects& e) { e.fog = hlod::FogEffect{0.03}; }},
      {"shadows", [](hlod::SceneEffects& e) { e.shadows = hlod::ShadowEffect{1024}; }},
      {"ssao", [](hlod::SceneEffects& e) { e.ssao = hlod::SsaoEffect{}; }},
      {"outline", [](hlod::SceneEffects& e) { e.outline = hlod::OutlineEffect{}; }},
  };
  const bool update = std::getenv("HLODR_UPDATE_GOLDEN") != nullptr;
  hlod::SceneEffects effects = bare();
  hlod::Image previous;
  for (const Step& step : steps) {
    step.add(effects);
    const Shot s = render(*ctx, effects, meshes);
    const std::string golden =
        std::string(HLODR_TEST_DATA) + "/golden/effects_" + step.name + ".png";
    if (update) {
      ASSERT_TRUE(renderer::writeImage(golden, s.image));
    }
    auto expected = hlod::loadImage(golden);
    ASSERT_TRUE(expected) << step.name << ": " << expected.message();
    const ImageDiff d = compare(s.image, *expected);
    // Rasterisers may differ in the last bit of edge coverage, filtering and dithering.
    EXPECT_LT(d.meanAbs, 1.0) << step.name;
    EXPECT_LT(d.differingShare, 0.01) << step.name;
    if (!previous.empty()) {
      const ImageDiff changed = compare(s.image, previous);
      EXPECT_GT(changed.differingShare, 0.01) << step.name << " changed too little";
    }
    previous = s.image;
  }
}

TEST(Effects, EachVariantCompilesOnceHoweverManyFramesAndMeshes) {
  auto ctx = context();
  if (!ctx) GTEST_SKIP() << "no GL context";
  auto e = litWithSun();
  e.textures = true;
  auto meshes = boxOnGround();
  meshes[1].texture = checker();
  const Shot s = render(*ctx, e, meshes, {0, -14, 9}, {0, 0, 0}, 5);
  EXPECT_EQ(s.compilesBefore, 2);  // textured and untextured, both at creation
  EXPECT_EQ(s.compilesAfter, s.compilesBefore);
  EXPECT_EQ(s.resources.programs, 2);
}

TEST(Effects, FogBrightensFarGroundTowardsTheFogColourAndLeavesNearGroundAlmostAlone) {
  auto ctx = context();
  if (!ctx) GTEST_SKIP() << "no GL context";
  // A long dark ground seen from low down: near and far pixels of the same surface.
  std::vector<hlod::Mesh> ground = {quad(-30, -10, 30, 150, 0, {0.2f, 0.2f, 0.2f, 1})};
  auto e = bare();
  e.background.colour = {1.0f, 1.0f, 1.0f};
  const glm::dvec3 eye(0, -10, 3), target(0, 30, 0);
  const Shot clear = render(*ctx, e, ground, eye, target);
  e.fog = hlod::FogEffect{0.02};
  const Shot foggy = render(*ctx, e, ground, eye, target);
  const glm::ivec2 nearPx = project(clear.view, {0, -4, 0});
  const glm::ivec2 farPx = project(clear.view, {0, 100, 0});
  const double nearClear = luminance(clear.image, nearPx), farClear = luminance(clear.image, farPx);
  const double nearFog = luminance(foggy.image, nearPx), farFog = luminance(foggy.image, farPx);
  EXPECT_NEAR(farClear, nearClear, 2.0);  // unlit: the same colour everywhere without fog
  // d = 110 m: exp(-2.2) = 11% of the surface left; d ~ 7 m: 87%.
  EXPECT_GT(farFog, farClear + 150.0);
  EXPECT_LT(nearFog - nearClear, 40.0);
  EXPECT_GT(farFog, nearFog + 100.0);
}

TEST(Effects, FogWithDensityZeroDerivesOneFromTheViewDistance) {
  auto ctx = context();
  if (!ctx) GTEST_SKIP() << "no GL context";
  // Before: density 0 went to the shader as 0, exp(0) = 1, and the fog did nothing.
  std::vector<hlod::Mesh> ground = {quad(-30, -10, 30, 150, 0, {0.2f, 0.2f, 0.2f, 1})};
  auto e = bare();
  e.background.colour = {1.0f, 1.0f, 1.0f};
  const Shot clear = render(*ctx, e, ground, {0, -10, 3}, {0, 30, 0});
  e.fog = hlod::FogEffect{0.0};
  const Shot derived = render(*ctx, e, ground, {0, -10, 3}, {0, 30, 0});
  const glm::ivec2 farPx = project(clear.view, {0, 100, 0});
  // far plane 200: density 1/200, d = 110: 42% of the surface left.
  const double expected = 255.0 - (255.0 - 51.0) * std::exp(-110.0 / 200.0);
  EXPECT_NEAR(luminance(derived.image, farPx), expected, 12.0);
  EXPECT_GT(luminance(derived.image, farPx), luminance(clear.image, farPx) + 60.0);
}

TEST(Effects, ShadowMapDarkensTheGroundBehindTheBoxAwayFromTheSun) {
  auto ctx = context();
  if (!ctx) GTEST_SKIP() << "no GL context";
  auto e = litWithSun();  // sun towards +x (and a little +y), 31 degrees above the horizon
  const Shot lit = render(*ctx, e, boxOnGround());
  e.shadows = hlod::ShadowEffect{1024};
  const Shot shadowed = render(*ctx, e, boxOnGround());
  // The box (4 m tall) casts its shadow towards -x: the ground at x = -3 is behind it.
  const glm::ivec2 behind = project(lit.view, {-3.5, -0.4, 0});
  const glm::ivec2 open = project(lit.view, {4, -3, 0});
  EXPECT_LT(luminance(shadowed.image, behind), luminance(lit.image, behind) - 40.0);
  EXPECT_NEAR(luminance(shadowed.image, open), luminance(lit.image, open), 3.0);
  // The shadow has the ambient light left: darker, not black.
  EXPECT_GT(luminance(shadowed.image, behind), 40.0);
}

TEST(Effects, SsaoDarkensTheCreaseWhereTheBoxMeetsTheGround) {
  auto ctx = context();
  if (!ctx) GTEST_SKIP() << "no GL context";
  auto e = bare();
  const Shot flat = render(*ctx, e, boxOnGround());
  e.ssao = hlod::SsaoEffect{};
  e.ssao->radius = 1.0;
  const Shot ao = render(*ctx, e, boxOnGround());
  // Unlit: without SSAO the ground is one colour; with it, the foot of the box darkens.
  const glm::ivec2 crease = project(flat.view, {0, -1.2, 0});
  const glm::ivec2 open = project(flat.view, {6, -6, 0});
  EXPECT_LT(luminance(ao.image, crease), luminance(flat.image, crease) - 15.0);
  EXPECT_NEAR(luminance(ao.image, open), luminance(flat.image, open), 4.0);
}

TEST(Effects, OutlineDarkensSilhouettesAndLeavesFacesAlone) {
  auto ctx = context();
  if (!ctx) GTEST_SKIP() << "no GL context";
  auto e = bare();
  const std::vector<hlod::Mesh> scene = {box({0, 0, 2}, {1, 1, 2}, {0.9f, 0.9f, 0.9f, 1})};
  const Shot plain = render(*ctx, e, scene);
  e.outline = hlod::OutlineEffect{};
  const Shot outlined = render(*ctx, e, scene);
  // Count dark pixels: the outline adds a line around the box, faces keep their colour.
  auto dark = [](const hlod::Image& img) {
    int n = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) n += pixel(img, x, y).r < 60;
    return n;
  };
  EXPECT_EQ(dark(plain.image), 0);
  EXPECT_GT(dark(outlined.image), 100);
  const glm::ivec2 face = project(plain.view, {0, -1, 2});
  EXPECT_NEAR(luminance(outlined.image, face), luminance(plain.image, face), 3.0);
}
