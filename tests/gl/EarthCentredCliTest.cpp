// A terrain in earth-centred coordinates through the `hlodr` executable, as a new user tries it:
// `hlodr build terrain.ply`, `hlodr path STORE --kind orbit`, then render. Every orbit frame shows
// the terrain (before, the orbit turned about y, sideways on the globe: empty sky), and `hlodr
// render terrain.ply` frames it from above too.
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "RunHlodr.h"
#include "hlod/geodesy/Geodesy.h"
#include "hlod/import/Import.h"

namespace fs = std::filesystem;

namespace {

// Share of pixels that differ from the top-left corner's colour (the background there).
double coverage(const fs::path& png) {
  auto img = hlod::loadImage(png);
  if (!img) return -1.0;
  std::size_t n = 0;
  const std::uint8_t* c = img->pixels.data();
  for (std::size_t i = 0; i < img->pixels.size(); i += 4)
    n += std::abs(int(img->pixels[i]) - c[0]) + std::abs(int(img->pixels[i + 1]) - c[1]) +
             std::abs(int(img->pixels[i + 2]) - c[2]) >
         12;
  return double(n) / double(img->pixels.size() / 4);
}

class EarthCentredCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("hlodr_ecef_" + std::to_string(::getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
    // 3 km x 3 km of hills near Zurich, 40 x 40 quads, in ECEF metres (double precision).
    const hlod::EnuFrame enu(hlod::LatLon{47.37, 8.54, 400.0});
    const int n = 40;
    std::ofstream ply(dir / "terrain.ply");
    ply.precision(17);
    ply << "ply\nformat ascii 1.0\nelement vertex " << (n + 1) * (n + 1)
        << "\nproperty double x\nproperty double y\nproperty double z\nelement face " << n * n * 2
        << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x) {
        const double e = 3000.0 * x / n - 1500.0, no = 3000.0 * y / n - 1500.0;
        const glm::dvec3 p = enu.toEcef({e, no, 60.0 * std::sin(e / 400.0) * std::cos(no / 500.0)});
        ply << p.x << " " << p.y << " " << p.z << "\n";
      }
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const int a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
        ply << "3 " << a << " " << b << " " << d << "\n3 " << a << " " << d << " " << c << "\n";
      }
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  fs::path dir;
};

TEST_F(EarthCentredCli, EveryOrbitFrameOfATerrainInEcefShowsTheTerrain) {
  auto r = gltest::runHlodr("build " + path("terrain.ply") + " -o " + path("t.hlod") + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  r = gltest::runHlodr("path " + path("t.hlod") + " --kind orbit -o " + path("orbit.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  r = gltest::runHlodr("render " + path("t.hlod") + " --path " + path("orbit.json") +
                       " --selector full --mode settled --frames 4 --size 160x90 -o " +
                       path("frames"));
  ASSERT_EQ(r.status, 0) << r.output;
  for (int f = 0; f < 4; ++f) {
    const std::string frame = "frames/frame_0000" + std::to_string(f) + ".png";
    EXPECT_GT(coverage(dir / frame), 0.05) << frame << " is (almost) empty sky";
  }
  // The street paths say why they do not apply, and what does.
  r = gltest::runHlodr("path " + path("t.hlod") + " --kind walk-fly -o " + path("w.json"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--kind orbit"), std::string::npos) << r.output;
}

TEST_F(EarthCentredCli, RenderingTheTerrainFileFramesItFromAbove) {
  const auto r =
      gltest::runHlodr("render " + path("terrain.ply") + " -o " + path("t.png") + " --size 160x90");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_GT(coverage(dir / "t.png"), 0.05);
}

}  // namespace
