// The up axis end to end: `hlodr build` stores the input's convention or --up, `hlodr info`
// prints it, `hlodr path --kind orbit` circles it, the city kinds refuse a y-up store, and the
// glTF engine of the shared data renders framed in the middle of its orbit's first frame.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "GlTestScene.h"
#include "RunHlodr.h"
#include "hlod/import/Import.h"
#include "hlod/runtime/CameraPath.h"

namespace fs = std::filesystem;

namespace {

class UpAxisCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("hlodr_upaxis_" + std::to_string(::getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
    // A tall box, 1 x 4 x 1, standing on y as an OBJ model does.
    std::ofstream obj(dir / "tall.obj");
    for (int i = 0; i < 8; ++i)
      obj << "v " << (i & 1) << " " << 4 * ((i >> 1) & 1) << " " << ((i >> 2) & 1) << "\n";
    obj << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  fs::path dir;
};

}  // namespace

TEST_F(UpAxisCli, BuildStoresTheConventionOrTheUpOptionAndInfoPrintsIt) {
  auto b = gltest::runHlodr("build " + path("tall.obj") + " -o " + path("y.hlod") + " --quiet");
  ASSERT_EQ(b.status, 0) << b.output;
  auto i = gltest::runHlodr("info " + path("y.hlod"));
  EXPECT_NE(i.output.find("up axis       y"), std::string::npos) << i.output;
  EXPECT_NE(i.output.find("CRS           none"), std::string::npos) << i.output;
  EXPECT_NE(i.output.find("tris/node     leaves: min"), std::string::npos) << i.output;
  EXPECT_NE(i.output.find("leaf / input  "), std::string::npos) << i.output;

  b = gltest::runHlodr("build " + path("tall.obj") + " -o " + path("z.hlod") + " --up z --quiet");
  ASSERT_EQ(b.status, 0) << b.output;
  i = gltest::runHlodr("info " + path("z.hlod") + " --json");
  EXPECT_NE(i.output.find("\"up\": \"z\""), std::string::npos) << i.output;

  b = gltest::runHlodr("build " + path("tall.obj") + " -o " + path("w.hlod") + " --up w");
  EXPECT_EQ(b.status, 2);
  EXPECT_NE(b.output.find("--up must be x, y or z"), std::string::npos) << b.output;
}

TEST_F(UpAxisCli, OrbitCirclesTheStoresUpAxisAndCityKindsSuggestOrbit) {
  auto b = gltest::runHlodr("build " + path("tall.obj") + " -o " + path("y.hlod") + " --quiet");
  ASSERT_EQ(b.status, 0) << b.output;
  auto p = gltest::runHlodr("path " + path("y.hlod") + " --kind orbit -o " + path("o.json"));
  ASSERT_EQ(p.status, 0) << p.output;
  auto orbit = hlod::CameraPath::read(path("o.json"));
  ASSERT_TRUE(orbit) << orbit.message();
  for (const auto& k : orbit->keyframes()) {
    EXPECT_EQ(k.up, glm::dvec3(0.0, 1.0, 0.0));
    EXPECT_NEAR(k.position.y, orbit->keyframes()[0].position.y, 1e-9);
  }
  p = gltest::runHlodr("path " + path("y.hlod") + " --kind drive -o " + path("d.json"));
  EXPECT_EQ(p.status, 1);
  EXPECT_NE(p.output.find("drive path"), std::string::npos) << p.output;
  EXPECT_NE(p.output.find("--kind orbit"), std::string::npos) << p.output;
}

TEST_F(UpAxisCli, TheGltfEngineFillsTheMiddleOfItsOrbitsFirstFrame) {
  const fs::path engine = fs::path(HLODR_SHARED_DATA) / "2CylinderEngine.glb";
  if (!fs::exists(engine)) GTEST_SKIP() << "shared data not found: " << engine;
  auto b = gltest::runHlodr("build " + engine.string() + " -o " + path("e.hlod") + " --quiet");
  ASSERT_EQ(b.status, 0) << b.output;
  auto p = gltest::runHlodr("path " + path("e.hlod") + " --kind orbit -o " + path("o.json"));
  ASSERT_EQ(p.status, 0) << p.output;
  auto r = gltest::runHlodr("render " + path("e.hlod") + " --path " + path("o.json") + " -o " +
                            path("frames") + " --frames 1 --mode settled --size 320x180 --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  auto img = hlod::loadImage(path("frames/frame_00000.png"));
  ASSERT_TRUE(img) << img.message();
  // The box of the pixels that differ from the background (the top-left pixel).
  const glm::ivec4 sky = gltest::pixel(*img, 0, 0);
  int x0 = img->width, x1 = -1, y0 = img->height, y1 = -1;
  for (int y = 0; y < img->height; ++y)
    for (int x = 0; x < img->width; ++x) {
      const glm::ivec4 d = glm::abs(gltest::pixel(*img, x, y) - sky);
      if (d.r + d.g + d.b < 30) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  ASSERT_GE(x1, 0) << "nothing drawn";
  // Lying on its side, circled around z, the engine was a small stripe; upright and framed
  // by its bounding sphere it spans about half the width, in the middle.
  EXPECT_GT(x1 - x0, img->width * 35 / 100);
  EXPECT_GT(y1 - y0, img->height * 20 / 100);
  EXPECT_NEAR((x0 + x1) / 2.0, img->width / 2.0, img->width * 0.1);
  EXPECT_NEAR((y0 + y1) / 2.0, img->height / 2.0, img->height * 0.15);
  EXPECT_GT(x0, 0);
  EXPECT_LT(x1, img->width - 1);
}
