// 3D Tiles through the `hlodr` executable as a user runs it: a city store exported and read back
// draws the same full-detail frames (exactly: every byte of the PNGs), a broken tileset is
// refused naming the tile, and the Mars tileset renders from the camera paths hlodr makes.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "RunHlodr.h"
#include "hlod/import/Import.h"

namespace fs = std::filesystem;

namespace {

std::string bytesOf(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class TilesetCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("hlodr_tiles_" + std::to_string(::getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  gltest::Run hlodr(const std::string& args) { return gltest::runHlodr(args); }
  fs::path dir;
};

TEST_F(TilesetCli, AStoreExportedAndReadBackDrawsTheSameFullDetailFrames) {
  ASSERT_EQ(hlodr("city -o " + path("city") + " --blocks 2 --quiet").status, 0);
  auto r = hlodr("build " + path("city") + " -o " + path("city.hlod") + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  r = hlodr("export-3dtiles " + path("city.hlod") + " -o " + path("tiles"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("on the globe: east-north-up"), std::string::npos) << r.output;
  r = hlodr("build " + path("tiles/tileset.json") + " -o " + path("back.hlod"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("an hlodr export, read back as its store"), std::string::npos)
      << r.output;
  r = hlodr("path " + path("city.hlod") + " --kind walk-fly -o " + path("walk.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* store : {"city", "back"}) {
    r = hlodr("render " + path(std::string(store) + ".hlod") + " --path " + path("walk.json") +
              " --selector full --mode settled --frames 3 --size 320x180 -o " + path(store));
    ASSERT_EQ(r.status, 0) << r.output;
  }
  for (const char* frame : {"frame_00000.png", "frame_00001.png", "frame_00002.png"}) {
    const std::string a = bytesOf(dir / "city" / frame), b = bytesOf(dir / "back" / frame);
    ASSERT_FALSE(a.empty()) << frame;
    EXPECT_TRUE(a == b) << frame << " differs between the store and its export read back";
  }
}

TEST_F(TilesetCli, ABrokenTilesetIsRefusedNamingTheTileAndNoStoreIsLeft) {
  std::ofstream(dir / "tileset.json")
      << R"({"asset":{"version":"1.1"},"geometricError":10,"root":{"refine":"REPLACE",
            "boundingVolume":{"box":[0,0,0,1,0,0,0,1,0,0,0,1]},"geometricError":5,
            "children":[{"boundingVolume":{"sphere":[0,0,0,1]},"geometricError":0,
                         "content":{"uri":"gone.glb"}}]}})";
  const auto r = hlodr("build " + path("tileset.json") + " -o " + path("t.hlod"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("tileset.json: tile root/0: content 'gone.glb' not found"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "t.hlod"));
}

TEST_F(TilesetCli, TheMarsTilesetRendersFromAnOrbitHlodrMakesUnderABudget) {
  const fs::path mars = fs::path(HLODR_SHARED_DATA) / "mars-tileset/tileset.json";
  if (!fs::exists(mars)) GTEST_SKIP() << "shared data not found: " << mars;
  auto r = hlodr("build " + mars.string() + " -o " + path("mars.hlod") + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  r = hlodr("path " + path("mars.hlod") + " --kind orbit -o " + path("orbit.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  r = hlodr("render " + path("mars.hlod") + " --path " + path("orbit.json") +
            " --selector lakhia --budget-ms 16 --mode settled --frames 2 --size 160x90 -o " +
            path("frames"));
  ASSERT_EQ(r.status, 0) << r.output;
  // The terrain stands on y (its surfaces face y): an orbit about y sees it in every frame.
  for (const char* frame : {"frame_00000.png", "frame_00001.png"}) {
    auto img = hlod::loadImage(dir / "frames" / frame);
    ASSERT_TRUE(img) << img.message();
    std::size_t terrain = 0;
    const std::uint8_t* corner = img->pixels.data();
    for (std::size_t i = 0; i < img->pixels.size(); i += 4)
      terrain += std::abs(int(img->pixels[i]) - int(corner[0])) +
                     std::abs(int(img->pixels[i + 1]) - int(corner[1])) +
                     std::abs(int(img->pixels[i + 2]) - int(corner[2])) >
                 12;
    EXPECT_GT(terrain, img->pixels.size() / 4 / 20) << frame << ": less than 5% terrain";
  }
}

}  // namespace
