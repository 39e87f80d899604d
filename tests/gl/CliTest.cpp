// End-to-end tests of the `hlodr` executable as a user runs it: exit codes, messages, outputs.
#include <sys/wait.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "GlTestScene.h"
#include "RunHlodr.h"
#include "hlod/import/Import.h"
#include "renderer/GlContext.h"

namespace fs = std::filesystem;

namespace {

gltest::Run hlodr(const std::string& args, const std::string& env = "") {
  return gltest::runHlodr(args, env);
}

// Pixels that differ from the default background: where geometry is.
int coveredPixels(const hlod::Image& img) {
  int covered = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const auto p = gltest::pixel(img, x, y);
      covered += std::abs(p.r - 179) + std::abs(p.g - 204) + std::abs(p.b - 230) > 30;
    }
  return covered;
}

class HlodrCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("hlodr_cli_" + std::to_string(::getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
    // A small OFF model: a tetrahedron.
    std::ofstream off(dir / "tetra.off");
    off << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  fs::path dir;
};

}  // namespace

TEST_F(HlodrCli, RendersAMeshFileAndPrintsTimesAndTriangles) {
  const auto r = hlodr("render " + path("tetra.off") + " -o " + path("t.png") + " --size 64x48");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("4 triangles"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("ms (wall, through glFinish)"), std::string::npos) << r.output;
  // The GPU's own time only where the renderer (named on the GL backend line) times it.
  EXPECT_NE(r.output.find("GL backend"), std::string::npos);
  EXPECT_EQ(r.output.find("GPU") != std::string::npos, renderer::timerQueriesTimeTheGpu(r.output))
      << r.output;
  auto img = hlod::loadImage(path("t.png"));
  ASSERT_TRUE(img) << img.message();
  EXPECT_EQ(img->width, 64);
  EXPECT_EQ(img->height, 48);
}

TEST_F(HlodrCli, ACityJsonFileIsDrawnWithADrawCallPerColourNotPerMaterial) {
  // Six surfaces, each with a material of its own, in three colours.
  const auto r = hlodr("render " + std::string(HLODR_TEST_DATA) + "/six-materials.city.json -o " +
                       path("m.png") + " --size 64x48");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("6 triangles, 3 draw calls"), std::string::npos) << r.output;
}

TEST_F(HlodrCli, EglAndOsMesaBackendsRenderTheSameFrame) {
  const std::string args = "render " + path("tetra.off") + " --size 96x64 -o ";
  const auto a = hlodr(args + path("egl.png"), "HLODR_GL_BACKEND=egl");
  ASSERT_EQ(a.status, 0) << a.output;
  EXPECT_NE(a.output.find("GL backend egl"), std::string::npos) << a.output;
  const auto b = hlodr(args + path("osmesa.png"), "HLODR_GL_BACKEND=osmesa");
  ASSERT_EQ(b.status, 0) << b.output;
  EXPECT_NE(b.output.find("GL backend osmesa"), std::string::npos) << b.output;
  auto ia = hlod::loadImage(path("egl.png"));
  auto ib = hlod::loadImage(path("osmesa.png"));
  ASSERT_TRUE(ia && ib);
  // Stated tolerance: mean channel difference under 2/255 and under 2% of pixels differing.
  const auto d = gltest::compare(*ia, *ib);
  EXPECT_LT(d.meanAbs, 2.0);
  EXPECT_LT(d.differingShare, 0.02);
}

TEST_F(HlodrCli, WritesJpegAndExrByExtension) {
  for (const char* name : {"t.jpg", "t.exr"}) {
    const auto r = hlodr("render " + path("tetra.off") + " --size 32x32 -o " + path(name));
    ASSERT_EQ(r.status, 0) << r.output;
    auto img = hlod::loadImage(path(name));
    ASSERT_TRUE(img) << name << ": " << img.message();
    EXPECT_EQ(img->width, 32);
  }
}

TEST_F(HlodrCli, ReportsAMissingModelClearly) {
  const auto r = hlodr("render " + path("nope.obj") + " -o " + path("x.png"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("nope.obj"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("x.png")));
}

TEST_F(HlodrCli, ReportsACorruptMeshWithoutCrashing) {
  std::ofstream(dir / "bad.off") << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 7\n";
  const auto r = hlodr("render " + path("bad.off") + " -o " + path("x.png"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("bad.off"), std::string::npos) << r.output;
}

TEST_F(HlodrCli, RejectsBadOptionsWithUsageExitCode) {
  // A side past 8192 is a usage error before the model loads, with the range.
  const auto huge =
      hlodr("render " + path("tetra.off") + " -o " + path("x.png") + " --size 9000x10");
  EXPECT_EQ(huge.status, 2);
  EXPECT_NE(huge.output.find("--size must look like 1280x720 (16..8192 each side), not '9000x10'"),
            std::string::npos)
      << huge.output;
  EXPECT_EQ(hlodr("render " + path("tetra.off") + " -o " + path("x.png") + " --size big").status,
            2);
  EXPECT_EQ(
      hlodr("render " + path("tetra.off") + " -o " + path("x.png") + " --camera 1,2,3").status, 2);
  EXPECT_EQ(hlodr("render " + path("tetra.off") + " --frobnicate").status, 2);
  EXPECT_EQ(hlodr("no-such-command").status, 2);
}

// A second model was ignored with exit 0 (a regression: it was a usage error before).
TEST_F(HlodrCli, TwoModelsAreAUsageErrorNamingTheSecond) {
  const auto r = hlodr("render " + path("tetra.off") + " /nonexistent/zzz.obj -o " + path("x.png"));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("give one MODEL, not 2 ('/nonexistent/zzz.obj' is the second)"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(path("x.png")));
}

// `hlodr render STORE` without a path: one frame under the budget, as POST /api/render draws
// it, from the store's framing or a --camera; what only a path run takes is refused.
TEST_F(HlodrCli, RendersOneBudgetBoundFrameOfAStoreWithoutAPath) {
  const auto c = hlodr("city -o " + path("city") + " --blocks 1 --texture 64 --quiet");
  ASSERT_EQ(c.status, 0) << c.output;
  const auto b = hlodr("build " + path("city") + " -o " + path("c.hlod") + " --quiet");
  ASSERT_EQ(b.status, 0) << b.output;
  const auto r =
      hlodr("render " + path("c.hlod") + " --budget-ms 33 --mode settled --size 160x90 -o " +
            path("f.png") + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("settled frame"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("of the 33.0 ms budget"), std::string::npos) << r.output;
  auto img = hlod::loadImage(path("f.png"));
  ASSERT_TRUE(img);
  EXPECT_EQ(img->width, 160);
  // The city is in view (this one-block strip covers about 4% of the frame), and the budget's
  // frame covers what every leaf drawn (--selector full) covers: no hole, no missing block.
  const auto full = hlodr("render " + path("c.hlod") + " --selector full --size 160x90 -o " +
                          path("full.png") + " --quiet");
  ASSERT_EQ(full.status, 0) << full.output;
  auto fullImg = hlod::loadImage(path("full.png"));
  ASSERT_TRUE(fullImg);
  const int covered = coveredPixels(*img), fullCovered = coveredPixels(*fullImg);
  EXPECT_GT(fullCovered, img->width * img->height / 50);
  EXPECT_GT(covered, fullCovered * 9 / 10);
  // From a camera of its own: another frame.
  const auto at =
      hlodr("render " + path("c.hlod") + " --camera 0,-50,30,40,40,0 --size 160x90 -o " +
            path("g.png") + " --quiet");
  ASSERT_EQ(at.status, 0) << at.output;
  EXPECT_NE(at.output.find("settled frame"), std::string::npos);  // the default, as the API's
  const auto fps = hlodr("render " + path("c.hlod") + " --fps 10 -o " + path("h.png"));
  EXPECT_EQ(fps.status, 2) << fps.output;
  EXPECT_NE(fps.output.find("--fps is for a path"), std::string::npos) << fps.output;
  const auto budget = hlodr("render " + path("c.hlod") + " --budget-ms 0 -o " + path("h.png"));
  EXPECT_EQ(budget.status, 2) << budget.output;
  EXPECT_NE(budget.output.find("--budget-ms: 0 is outside [0.5, 10000]"), std::string::npos)
      << budget.output;
}

TEST_F(HlodrCli, AForcedBackendThatDoesNotExistIsAClearError) {
  const auto r =
      hlodr("render " + path("tetra.off") + " -o " + path("x.png"), "HLODR_GL_BACKEND=directx");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("directx"), std::string::npos) << r.output;
}

TEST_F(HlodrCli, GeneratesAndRendersASmallCity) {
  const auto c = hlodr("city -o " + path("city") + " --blocks 2 --texture 64 --quiet");
  ASSERT_EQ(c.status, 0) << c.output;
  const auto r = hlodr("render " + path("city") + " -o " + path("city.png") + " --size 160x90");
  ASSERT_EQ(r.status, 0) << r.output;
  auto img = hlod::loadImage(path("city.png"));
  ASSERT_TRUE(img);
  // Geometry covers a good part of the frame: many pixels differ from the background. The
  // default view frames the model's box (hlod::frameBounds): this flat city two blocks long
  // spans the frame's width and covers about a fifth of its pixels (framed by its bounding
  // sphere it covered about 6%).
  const int covered = coveredPixels(*img);
  EXPECT_GT(covered, img->width * img->height / 8);
}

TEST_F(HlodrCli, RenderTakesASceneFileAndNamesTheFieldOfABadOne) {
  std::ofstream(path("sky.json")) << R"({"background": {"sky": {"horizon": [0.9, 0.9, 1]}},
      "effects": {"shading": "lambert", "sun": true, "outline": true}})";
  const auto ok = hlodr("render " + path("tetra.off") + " -o " + path("s.png") +
                        " --size 64x48 --scene " + path("sky.json"));
  ASSERT_EQ(ok.status, 0) << ok.output;
  const auto plain =
      hlodr("render " + path("tetra.off") + " -o " + path("p.png") + " --size 64x48");
  ASSERT_EQ(plain.status, 0) << plain.output;
  auto a = hlod::loadImage(path("s.png")), b = hlod::loadImage(path("p.png"));
  ASSERT_TRUE(a && b);
  EXPECT_GT(gltest::compare(*a, *b).differingShare, 0.3);  // the sky behind the model

  std::ofstream(path("bad.json")) << R"({"effects": {"fog": {"density": "thick"}}})";
  const auto bad = hlodr("render " + path("tetra.off") + " -o " + path("b.png") + " --scene " +
                         path("bad.json"));
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("bad.json: effects.fog.density: must be a number in 0..1"),
            std::string::npos)
      << bad.output;
  const auto both = hlodr("render " + path("tetra.off") + " -o " + path("b.png") +
                          " --fog --scene " + path("sky.json"));
  EXPECT_EQ(both.status, 2);
  EXPECT_NE(both.output.find("--fog and --scene"), std::string::npos) << both.output;
}

TEST_F(HlodrCli, StudyBuildComparesTheSimplifiersPerLevelAndWritesJsonAndCsv) {
#ifdef HLODR_SANITIZE_BUILD
  // 4-15x slower under the sanitizers: a wavy sheet of 7,200 triangles, not a 39k city block.
  {
    std::ofstream obj(dir / "sheet.obj");
    const int n = 60;
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x)
        obj << "v " << x << " " << y << " " << 3.0 * std::sin(0.3 * x) * std::cos(0.2 * y) << "\n";
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const int a = y * (n + 1) + x + 1;
        obj << "f " << a << " " << a + 1 << " " << a + n + 2 << " " << a + n + 1 << "\n";
      }
  }
  const std::string model = path("sheet.obj"), samples = "300";
#else
  const auto c = hlodr("city -o " + path("city") + " --blocks 1 --texture 64 --quiet");
  ASSERT_EQ(c.status, 0) << c.output;
  const std::string model = path("city"), samples = "2000";
#endif
  const auto r = hlodr("study-build " + model + " -o " + path("sb") + " --samples " + samples +
                       " --desired-tris 2000 --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("hausdorff"), std::string::npos) << r.output;
  std::ifstream csv(dir / "sb" / "build-study.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("hierarchy,simplifier,buildSeconds,level,", 0), 0u) << header;
  int rows[2] = {0, 0};
  std::string last[2];
  while (std::getline(csv, line)) {
    EXPECT_EQ(line.rfind("planes,", 0), 0u) << line;  // the default: --hierarchy planes
    const int k = line.rfind("planes,openmesh", 0) == 0 ? 1 : 0;
    ++rows[k];
    last[k] = line;
  }
  EXPECT_GE(rows[0], 2);
  EXPECT_EQ(rows[0], rows[1]);  // both simplifiers, the same levels
  // The deepest cut is the leaves, the original triangles: no distance (column 8, hausdorff).
  for (const std::string& l : last) {
    std::size_t at = 0;
    for (int comma = 0; comma < 7; ++comma) at = l.find(',', at) + 1;
    EXPECT_LT(std::stod(l.substr(at)), 1e-6) << l;
  }
  EXPECT_TRUE(fs::exists(dir / "sb" / "build-study.json"));
  const auto bad = hlodr("study-build " + model + " --simplifiers qslim");
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_NE(bad.output.find("qslim"), std::string::npos) << bad.output;
}

TEST_F(HlodrCli, StudyPassesParamsToTheStudiedRunsAndNamesAWrongOne) {
  const auto c = hlodr("city -o " + path("city") + " --blocks 1 --texture 64 --quiet");
  ASSERT_EQ(c.status, 0) << c.output;
  const auto b = hlodr("build " + path("city") + " -o " + path("c.hlod") + " --quiet");
  ASSERT_EQ(b.status, 0) << b.output;
  const std::string study = "study " + path("c.hlod") +
                            " --kind orbit --frames 2 --budgets 33 --selectors lakhia "
                            "--sse-px 4 --strips 0 --size 160x90 --quiet ";
  const auto r = hlodr(study + "-o " + path("st") + " --params progressive=0 --splats on");
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream report(dir / "st" / "study.json");
  std::stringstream text;
  text << report.rdbuf();
  EXPECT_NE(text.str().find("\"params\": \"progressive=0\""), std::string::npos);
  EXPECT_NE(text.str().find("\"splats\": true"), std::string::npos);
  const auto maybe = hlodr(study + "-o " + path("st3") + " --splats maybe");
  EXPECT_EQ(maybe.status, 2) << maybe.output;
  EXPECT_NE(maybe.output.find("--splats"), std::string::npos) << maybe.output;
  const auto bad = hlodr(study + "-o " + path("st2") + " --params nope=1");
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_NE(bad.output.find("nope"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(dir / "st2"));
}

// View-dependent rendering end to end: a store built with --vdr, drawn along an orbit under a
// tight budget (a bound of a pixel or so, so that the front moves as the camera goes round).
// Each frame refines the clusters again; one whose faces changed must be drawn from its new
// arrays, not from the GPU copy of an earlier frame, which drew the old front's triangles where
// the new one had moved: holes and shards, 18-24 dB against the full-detail frames (32-39 dB
// without them; the median is asserted, each frame's front being the budget's).
TEST_F(HlodrCli, ViewDependentFramesMatchTheFullDetailFrames) {
  {
    std::ofstream off(dir / "sphere.off");
    const int rings = 120, segments = 180;
    off << "OFF\n" << (rings - 1) * segments + 2 << " " << 2 * segments * (rings - 1) << " 0\n";
    off << "0 1 0\n0 -1 0\n";
    for (int r = 1; r < rings; ++r)
      for (int s = 0; s < segments; ++s) {
        const double t = M_PI * r / rings, p = 2 * M_PI * s / segments;
        // A bumpy sphere: its levels differ from each other.
        const double rad = 1.0 + 0.05 * std::sin(9 * p) * std::sin(7 * t);
        off << rad * std::sin(t) * std::cos(p) << " " << rad * std::cos(t) << " "
            << rad * std::sin(t) * std::sin(p) << "\n";
      }
    const auto at = [&](int r, int s) { return 2 + (r - 1) * segments + (s % segments); };
    for (int s = 0; s < segments; ++s) {
      off << "3 0 " << at(1, s + 1) << " " << at(1, s) << "\n";
      off << "3 1 " << at(rings - 1, s) << " " << at(rings - 1, s + 1) << "\n";
      for (int r = 1; r + 1 < rings; ++r) {
        off << "3 " << at(r, s) << " " << at(r, s + 1) << " " << at(r + 1, s) << "\n";
        off << "3 " << at(r + 1, s) << " " << at(r, s + 1) << " " << at(r + 1, s + 1) << "\n";
      }
    }
  }
  auto r = hlodr("build " + path("sphere.off") + " --vdr --quiet -o " + path("s.hlod"));
  ASSERT_EQ(r.status, 0) << r.output;
  r = hlodr("path " + path("s.hlod") + " --kind orbit -o " + path("p.json"));
  ASSERT_EQ(r.status, 0) << r.output;
#ifdef HLODR_SANITIZE_BUILD
  const std::string budget = "6";  // the refinement's CPU time counts in the frame
#else
  const std::string budget = "3";
#endif
  for (const char* s : {"vdr", "full"}) {
    r = hlodr("render " + path("s.hlod") + " --path " + path("p.json") + " --selector " + s +
              " --budget-ms " + budget + " --mode settled --fps 0.2 --size 320x240 --quiet -o " +
              path(s));
    ASSERT_EQ(r.status, 0) << s << ": " << r.output;
  }
  std::vector<double> psnrs;
  for (int f = 0;; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.png", f);
    if (!fs::exists(dir / "full" / name)) break;
    auto full = hlod::loadImage(dir / "full" / name);
    auto vdr = hlod::loadImage(dir / "vdr" / name);
    ASSERT_TRUE(full && vdr) << name;
    ASSERT_GT(coveredPixels(*full), 1000) << name;
    double sum = 0.0;
    for (int y = 0; y < full->height; ++y)
      for (int x = 0; x < full->width; ++x) {
        const glm::ivec4 d = gltest::pixel(*full, x, y) - gltest::pixel(*vdr, x, y);
        sum += double(d.r * d.r + d.g * d.g + d.b * d.b) / 3.0;
      }
    const double mse = sum / (full->width * full->height);
    const double psnr = mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 100.0;
    std::printf("[ vdr      ] %s: PSNR %.1f dB against full detail\n", name, psnr);
    psnrs.push_back(psnr);
  }
  ASSERT_GE(psnrs.size(), 6u);
  std::nth_element(psnrs.begin(), psnrs.begin() + psnrs.size() / 2, psnrs.end());
  EXPECT_GT(psnrs[psnrs.size() / 2], 28.0);
}
