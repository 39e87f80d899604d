#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "RuntimeTestScene.h"
#include "hlod/runtime/CameraPath.h"
#include "hlod/runtime/FrameStats.h"
#include "hlod/runtime/LakhiaSelector.h"
#include "hlod/runtime/Loader.h"
#include "hlod/runtime/Plots.h"

namespace hlod {
namespace {

std::vector<FrameRecord> handMadeFrames() {
  // gpuMs 10, 20, 30, 40 against a 20 ms target: relative errors 0.5, 0, 0.5, 1.
  std::vector<FrameRecord> f(4);
  for (int i = 0; i < 4; ++i) {
    f[i].index = i;
    f[i].time = i / 30.0;
    f[i].targetMs = 20.0;
    f[i].gpuMs = 10.0 * (i + 1);
    f[i].upToggles = i;
    f[i].downToggles = 1;
    f[i].triangles = 1000 * (i + 1);
    f[i].coarserNotResident = i == 2 ? 6 : 0;
    f[i].residentBytes = 100 * (i + 1);
    f[i].capBytes = 1000;
    f[i].stalls = i == 3 ? 2 : 0;
    f[i].nodesPerLevel = {5, static_cast<std::uint32_t>(i)};
  }
  return f;
}

TEST(FrameStats, SummaryGivesErrorPercentilesSharesAndPeaks) {
  const auto frames = handMadeFrames();
  const FrameSummary s = summarize(frames);
  EXPECT_EQ(s.frames, 4u);
  EXPECT_DOUBLE_EQ(s.medianRelError, 0.5);  // nearest rank of {0, .5, .5, 1}
  EXPECT_DOUBLE_EQ(s.p95RelError, 1.0);
  EXPECT_DOUBLE_EQ(s.shareOverTarget, 0.5);  // 30 and 40
  EXPECT_DOUBLE_EQ(s.shareOver125, 0.5);     // > 25 ms
  EXPECT_DOUBLE_EQ(s.p99OverTarget, 2.0);
  EXPECT_DOUBLE_EQ(s.meanGpuMs, 25.0);
  EXPECT_EQ(s.totalStalls, 2u);
  EXPECT_EQ(s.peakResidentBytes, 400u);
  EXPECT_DOUBLE_EQ(s.peakOverCap, 0.4);
  EXPECT_DOUBLE_EQ(s.togglesPerFrame, (0 + 1 + 2 + 3 + 4) / 4.0);
  EXPECT_DOUBLE_EQ(s.meanTriangles, 2500.0);
  EXPECT_DOUBLE_EQ(s.coarserPerFrame, 1.5);
}

TEST(FrameStats, EmptyRunAndZeroTargetsGiveZerosNotNan) {
  const FrameSummary empty = summarize({});
  EXPECT_EQ(empty.frames, 0u);
  EXPECT_EQ(empty.medianRelError, 0.0);
  std::vector<FrameRecord> f(2);  // targetMs 0
  const FrameSummary s = summarize(f);
  EXPECT_EQ(s.p95RelError, 0.0);
  EXPECT_EQ(s.peakOverCap, 0.0);
  EXPECT_TRUE(nlohmann::json::accept(statsJson(f, s)));
}

TEST(FrameStats, JsonAndCsvCarryEveryDocumentedField) {
  const auto frames = handMadeFrames();
  const auto j = nlohmann::json::parse(statsJson(frames, summarize(frames)));
  ASSERT_EQ(j.at("frames").size(), 4u);
  for (const char* key :
       {"index", "time", "targetMs", "estimatedMs", "gpuMs", "cpuMs", "selectorMs", "triangles",
        "nodesPerLevel", "upToggles", "downToggles", "vTime", "residentBytes", "capBytes",
        "loadsStarted", "loadsFinished", "unloads", "coarserNotResident", "stalls"}) {
    EXPECT_TRUE(j["frames"][0].contains(key)) << key;
  }
  EXPECT_EQ(j["frames"][3]["gpuMs"].get<double>(), 40.0);
  EXPECT_EQ(j["summary"]["p99OverTarget"].get<double>(), 2.0);
  const std::string csv = statsCsv(frames);
  std::istringstream lines(csv);
  std::string header, row;
  std::getline(lines, header);
  EXPECT_NE(header.find("gpuMs"), std::string::npos);
  EXPECT_NE(header.find("level1"), std::string::npos);
  int rows = 0;
  while (std::getline(lines, row)) ++rows;
  EXPECT_EQ(rows, 4);
}

TEST(Plots, MovingAverageIsTrailingAndShorterAtTheStart) {
  const std::vector<double> v = {2, 4, 6, 8};
  const auto m = movingAverage(v, 2);
  EXPECT_EQ(m, (std::vector<double>{2, 3, 5, 7}));
}

TEST(Plots, ChartsHaveTitleAxesLegendAndOneLinePerSeries) {
  const auto frames = handMadeFrames();
  const std::string levels = levelsSvg(frames);
  EXPECT_NE(levels.find("<svg"), std::string::npos);
  EXPECT_NE(levels.find("HLODs drawn per level"), std::string::npos);
  EXPECT_NE(levels.find("hlod_1"), std::string::npos);
  auto count = [](const std::string& s, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count(levels, "<polyline"), 2u);
  EXPECT_EQ(count(togglesSvg(frames), "<polyline"), 4u);
  EXPECT_EQ(count(frameTimeSvg(frames), "<polyline"), 3u);
  EXPECT_NE(frameTimeSvg(frames).find("target"), std::string::npos);
  // No data and odd names: still a valid document, names escaped.
  PlotSpec spec;
  spec.title = "a < b & c";
  const std::string empty = lineChartSvg(spec);
  EXPECT_NE(empty.find("a &lt; b &amp; c"), std::string::npos);
  EXPECT_NE(empty.find("</svg>"), std::string::npos);
}

// A whole path run without GL: walk-fly over a synthetic city, Lakhia selector, loader stepped
// between frames, a simulated GPU. Writes stats and plots to HLODR_PLOT_DIR when set.
TEST(FrameStats, SimulatedWalkFlyRunStaysNearTheTargetAndShowsLevelsChanging) {
  test::SyntheticCity c;
  c.blocksX = c.blocksY = 8;
  c.depth = 4;
  test::MemoryNodeSource src(test::makeSyntheticCity(c));
  const Skeleton& sk = src.skeleton();
  auto path = makeWalkFlyPath(sk);
  ASSERT_TRUE(path.ok());
  LoaderParams lp;
  lp.chunkBytes = 64 * 1024;
  lp.capBytes = 400ull * 48000;  // 400 nodes
  Loader loader(src, lp);
  ASSERT_TRUE(loader.loadRoots().ok());
  SelectorParams sp;
  sp.lakhia.c_targetTime = 20.0;
  LakhiaSelector sel(sk, sp);
  ResidencySet gpu(sk.nodes.size());
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::vector<FrameRecord> frames;
  std::uint64_t index = 0;
  for (const CameraSample& cs : path->sampleAt(30.0)) {
    for (const LoaderEvent& e : loader.drainEvents()) {
      gpu.set(e.node, e.kind == LoaderEvent::Kind::Loaded);
    }
    View v;
    v.camera = cs.camera;
    v.velocity = cs.velocity;
    const Selection s = sel.select(v, gpu);
    loader.setWanted(s.loadPriorities);
    for (int k = 0; k < 3; ++k) loader.step();  // the loader's share of a frame
    double cost = 0.0;
    for (std::uint32_t n : s.front) cost += sk.nodes[n].cost;
    const double ms = 2e-5 * cost * (1.0 + noise(rng));
    sel.feedback(ms);
    FrameRecord r;
    r.index = index++;
    r.time = cs.time;
    r.gpuMs = r.cpuMs = ms;
    fillFromSelection(r, s);
    fillFromLoader(r, loader.counters());
    frames.push_back(r);
  }
  const FrameSummary sum = summarize(frames);
  EXPECT_LT(sum.shareOver125, 0.02);
  EXPECT_LE(sum.peakOverCap, 1.0);
  // Walking: the detailed levels are drawn; flying over everything: mostly coarse ones.
  const FrameRecord& walk = frames[300];
  const FrameRecord& fly = frames.back();
  EXPECT_GT(walk.nodesPerLevel.back() + walk.nodesPerLevel[c.depth - 1], 0u);
  EXPECT_GT(fly.nodesPerLevel[0] + fly.nodesPerLevel[1], fly.nodesPerLevel.back());
  if (const char* dir = std::getenv("HLODR_PLOT_DIR")) {
    const std::filesystem::path d(dir);
    ASSERT_TRUE(writeStatsJson((d / "stats.json").string(), frames, sum).ok());
    ASSERT_TRUE(writeStatsCsv((d / "stats.csv").string(), frames).ok());
    ASSERT_TRUE(writeSvg((d / "levels.svg").string(), levelsSvg(frames)).ok());
    ASSERT_TRUE(writeSvg((d / "toggles.svg").string(), togglesSvg(frames)).ok());
    ASSERT_TRUE(writeSvg((d / "frametime.svg").string(), frameTimeSvg(frames)).ok());
  }
}

}  // namespace
}  // namespace hlod
