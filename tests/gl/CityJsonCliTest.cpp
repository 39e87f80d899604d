// End to end on a real city model: `hlodr info` on the CityJSON file, `hlodr build` of it into
// a store, a camera path and one rendered frame of it, in which the roofs' colour must show.
#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "GlTestScene.h"
#include "RunHlodr.h"
#include "hlod/import/Import.h"

namespace fs = std::filesystem;

namespace {

const fs::path kRotterdam = fs::path(HLODR_SHARED_DATA) / "rotterdam-delfshaven.cityjson.json";

class CityJsonCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kRotterdam)) GTEST_SKIP() << "shared data not found: " << kRotterdam;
    dir = fs::temp_directory_path() /
          ("hlodr_cityjson_" + std::to_string(::getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
  }
  void TearDown() override {
    if (!dir.empty()) fs::remove_all(dir);
  }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  fs::path dir;
};

// Pixels of the roof palette colour (red-brown), lit or in shade.
int roofPixels(const hlod::Image& img) {
  int n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const auto p = gltest::pixel(img, x, y);
      n += p.r > p.g + 40 && p.r > p.b + 40;
    }
  return n;
}

}  // namespace

TEST_F(CityJsonCli, InfoOnTheModelPrintsFormatCrsObjectsLodAndExtent) {
  const auto r = gltest::runHlodr("info " + kRotterdam.string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* line :
       {"format        CityJSON 0.2", "CRS           EPSG:7415 (projected)", "city objects  853",
        "LoD           highest of each object (2)", "extent        1044.560 x 649.507 x 41.158"})
    EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
  const auto bad = gltest::runHlodr("info " + kRotterdam.string() + " --lod 3");
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.output.find("no city object has geometry at LoD 3"), std::string::npos)
      << bad.output;
}

TEST_F(CityJsonCli, BuildsAStoreAndRendersAFrameWithRoofsOnTheBuildings) {
  const auto b =
      gltest::runHlodr("build " + kRotterdam.string() + " -o " + path("r.hlod") + " --quiet");
  ASSERT_EQ(b.status, 0) << b.output;
  const auto i = gltest::runHlodr("info " + path("r.hlod"));
  ASSERT_EQ(i.status, 0) << i.output;
  EXPECT_NE(i.output.find("37411 input"), std::string::npos) << i.output;
  const auto p =
      gltest::runHlodr("path " + path("r.hlod") + " --kind orbit -o " + path("orbit.json"));
  ASSERT_EQ(p.status, 0) << p.output;
  const auto r =
      gltest::runHlodr("render " + path("r.hlod") + " --path " + path("orbit.json") + " -o " +
                       path("frames") + " --frames 1 --mode settled --size 320x180 --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  auto img = hlod::loadImage(path("frames/frame_00000.png"));
  ASSERT_TRUE(img) << img.message();
  // Seen from 30 degrees above, the roofs cover a good part of what the buildings cover.
  EXPECT_GT(roofPixels(*img), 320 * 180 / 100);
  // The model file itself renders Z-up (as CityJSON is) with the same roofs.
  const auto d = gltest::runHlodr("render " + kRotterdam.string() + " -o " + path("d.png") +
                                  " --size 320x180 --quiet");
  ASSERT_EQ(d.status, 0) << d.output;
  auto direct = hlod::loadImage(path("d.png"));
  ASSERT_TRUE(direct) << direct.message();
  EXPECT_GT(roofPixels(*direct), 320 * 180 / 100);
}
