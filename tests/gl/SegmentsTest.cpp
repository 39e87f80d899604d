// A path run split into segments (`hlodr render --segment I/N`, `hlodr concat`): settled
// segments joined are the unsplit run frame for frame, the join refuses a gap, and the CLI says
// what is wrong with a bad --segment. A tiny store of two procedural city blocks.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CachedStore.h"
#include "RunHlodr.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/city/City.h"
#include "hlod/runtime/CameraPath.h"
#include "hlod/store/NodeStore.h"
#include "service/SegmentJoin.h"
#include "service/Session.h"

namespace fs = std::filesystem;

namespace {

fs::path segmentsTestRoot() {
  return fs::temp_directory_path() / ("hlodr_segments_" + std::to_string(::getpid()));
}

const fs::path& segmentStore() {
  static const fs::path store = gltest::cachedStore("segments.hlod", [](const fs::path& dir) {
    hlod::BuildOptions bo;
    bo.desiredTri = 1500;
    auto builder = hlod::HlodBuilder::create(dir, bo);
    if (!builder) return false;
    hlod::CityOptions co;
    co.textureSize = 64;
    for (int i = 0; i < 2; ++i)
      if (!(*builder)->addBlock(hlod::generateBlock(co, i))) return false;
    return (*builder)->finish(0.0).ok();
  });
  return store;
}

std::string fileBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class SegmentsTest : public ::testing::Test {
 protected:
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(segmentsTestRoot(), ec);
  }
  void SetUp() override {
    ASSERT_FALSE(segmentStore().empty());
    auto store = hlod::NodeStore::open(segmentStore());
    ASSERT_TRUE(store.ok()) << store.message();
    auto p = hlod::makeOrbitPath((*store)->skeleton(), 2.0);
    ASSERT_TRUE(p.ok()) << p.message();
    path = std::make_unique<hlod::CameraPath>(std::move(*p));
    out = segmentsTestRoot() / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(out);
  }

  // The setting under which settled frames depend on the camera alone (docs/cli.md, Segments):
  // the sse selector (no measured time in its choice), no occlusion culling (auto switches on
  // measured time), no caps.
  static service::SessionOptions deterministic() {
    service::SessionOptions o;
    o.width = 96;
    o.height = 64;
    o.selector = "sse";
    o.selectorParams.ssePixels = 2.0;
    o.occlusion = hlod::OcclusionMode::Off;
    return o;
  }

  // Renders segment `index` of `count` (count 1: the whole run) into `dir`.
  void render(const fs::path& dir, std::uint32_t index, std::uint32_t count,
              std::uint64_t warmup = hlod::PathRunOptions::kDefaultWarmupFrames) {
    auto session = service::Session::open(segmentStore(), deterministic());
    ASSERT_TRUE(session.ok()) << session.message();
    hlod::PathRunOptions ro;
    ro.fps = 10.0;
    ro.maxFrames = kFrames;
    ro.mode = hlod::FrameMode::Settled;
    ro.segmentIndex = index;
    ro.segmentCount = count;
    ro.warmupFrames = warmup;
    service::FileOutputs fo;
    fo.output = dir;
    auto r = service::runPathToFiles(**session, *path, ro, fo);
    ASSERT_TRUE(r.ok()) << r.message();
  }

  static constexpr int kFrames = 16;
  std::unique_ptr<hlod::CameraPath> path;
  fs::path out;
};

}  // namespace

TEST_F(SegmentsTest, SettledSegmentsJoinedAreTheUnsplitRunFrameForFrame) {
  render(out / "whole", 0, 1);
  render(out / "part0", 0, 2);
  render(out / "part1", 1, 2, 4);
  // Given out of order: the join orders them by their frames.
  auto joined = service::joinSegments({out / "part1", out / "part0"}, out / "joined");
  ASSERT_TRUE(joined.ok()) << joined.message();
  EXPECT_EQ(joined->frames, std::uint64_t(kFrames));
  for (int i = 0; i < kFrames; ++i) {
    const std::string name =
        "frame_" + std::string(5 - std::to_string(i).size(), '0') + std::to_string(i) + ".png";
    const std::string whole = fileBytes(out / "whole" / name);
    ASSERT_FALSE(whole.empty()) << name;
    EXPECT_TRUE(whole == fileBytes(out / "joined" / name)) << name << " differs";
  }
  // One stats file as the unsplit run's: frames numbered on, the same fronts, one summary.
  auto read = [](const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in, nullptr, false);
  };
  const auto a = read(out / "whole" / "stats.json");
  const auto b = read(out / "joined" / "stats.json");
  ASSERT_TRUE(a.is_object() && b.is_object());
  ASSERT_EQ(b["frames"].size(), std::size_t(kFrames));
  for (int i = 0; i < kFrames; ++i) {
    EXPECT_EQ(b["frames"][i]["index"], i);
    EXPECT_EQ(b["frames"][i]["triangles"], a["frames"][i]["triangles"]) << "frame " << i;
    EXPECT_EQ(b["frames"][i]["nodesPerLevel"], a["frames"][i]["nodesPerLevel"]) << "frame " << i;
  }
  EXPECT_EQ(b["summary"]["frames"], kFrames);
  EXPECT_EQ(b["summary"]["meanTriangles"], a["summary"]["meanTriangles"]);
  EXPECT_EQ(b["segments"], 2);
  EXPECT_FALSE(b.contains("segment"));
  EXPECT_TRUE(fs::exists(out / "joined" / "stats.csv"));
}

TEST_F(SegmentsTest, ConcatRefusesAGapAndWritesNothing) {
  render(out / "part0", 0, 3);
  render(out / "part2", 2, 3);
  auto joined = service::joinSegments({out / "part0", out / "part2"}, out / "joined");
  ASSERT_FALSE(joined.ok());
  EXPECT_NE(joined.message().find("missing"), std::string::npos) << joined.message();
  EXPECT_FALSE(fs::exists(out / "joined"));
  // The command says the same and fails.
  const auto r = gltest::runHlodr("concat " + (out / "part0").string() + " " +
                                  (out / "part2").string() + " -o " + (out / "j2").string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("missing"), std::string::npos) << r.output;
  // A part that is not a segment's output.
  render(out / "whole", 0, 1);
  auto notSegment = service::joinSegments({out / "whole"}, out / "joined");
  ASSERT_FALSE(notSegment.ok());
  EXPECT_NE(notSegment.message().find("not a segment"), std::string::npos) << notSegment.message();
}

TEST_F(SegmentsTest, RenderSaysWhatIsWrongWithASegmentArgument) {
  const std::string base = "render " + segmentStore().string() + " --path " +
                           (out / "none.json").string() + " --size 32x32 -o " +
                           (out / "x").string() + " --segment ";
  fs::create_directories(out);
  ASSERT_TRUE(path->write((out / "none.json").string()).ok());
  // Each case a process (seconds under load): the forms are the unit test's (SegmentsTest).
  for (const char* bad : {"2/2", "a/2"}) {
    const auto r = gltest::runHlodr(base + bad);
    EXPECT_EQ(r.status, 2) << bad << ": " << r.output;
    EXPECT_NE(r.output.find("--segment"), std::string::npos) << r.output;
  }
  // More segments than frames.
  const auto r = gltest::runHlodr(base + "0/5 --frames 3");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("segments"), std::string::npos) << r.output;
  // --warmup without --segment.
  const auto w = gltest::runHlodr("render " + segmentStore().string() + " --path " +
                                  (out / "none.json").string() + " -o " + (out / "y").string() +
                                  " --warmup 5");
  EXPECT_EQ(w.status, 2) << w.output;
}
