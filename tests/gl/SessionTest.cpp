// Session on a real (software) GL context: a tiny node store built in the test from two
// procedural city blocks, an orbit path, settled and realtime runs, and the CLI end to end.
#include "RunHlodr.h"
#include "service/BatchedReference.h"
#include "service/Session.h"

#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CachedStore.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/city/City.h"
#include "hlod/store/NodeStore.h"

namespace fs = std::filesystem;

namespace {

fs::path testRoot() {
  return fs::temp_directory_path() / ("hlodr_pathsession_" + std::to_string(::getpid()));
}

// Two city blocks with small textures and small leaves, so the tree has several levels.
// Read only: one store for all the test processes (CachedStore.h).
const fs::path& tinyStore() {
  static const fs::path store = gltest::cachedStore("tiny.hlod", [](const fs::path& dir) {
    hlod::BuildOptions bo;
    bo.desiredTri = 1500;
    auto builder = hlod::HlodBuilder::create(dir, bo);
    EXPECT_TRUE(builder.ok()) << builder.message();
    if (!builder) return false;
    hlod::CityOptions co;
    co.textureSize = 64;
    for (int i = 0; i < 2; ++i) {
      auto s = (*builder)->addBlock(hlod::generateBlock(co, i));
      EXPECT_TRUE(s.ok()) << s.message();
      if (!s) return false;
    }
    auto skel = (*builder)->finish(0.0);
    EXPECT_TRUE(skel.ok()) << skel.message();
    return skel.ok();
  });
  return store;
}

class SessionTest : public ::testing::Test {
 protected:
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(testRoot(), ec);
  }
  void SetUp() override {
    auto store = hlod::NodeStore::open(tinyStore());
    ASSERT_TRUE(store.ok()) << store.message();
    skeleton = (*store)->skeleton();
    auto p = hlod::makeOrbitPath(skeleton, 2.0);
    ASSERT_TRUE(p.ok()) << p.message();
    path = std::make_unique<hlod::CameraPath>(std::move(*p));
    out = testRoot() / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(out);
  }

  service::SessionOptions smallOptions() const {
    service::SessionOptions o;
    o.width = 160;
    o.height = 90;
    o.budgetMs = 5.0;
    return o;
  }
  static std::vector<hlod::FrameRecord> frames(const service::Session& s) {
    return {s.recent().begin(), s.recent().end()};
  }

  std::uint64_t rootBytes() const {
    std::uint64_t b = 0;
    for (auto r : skeleton.roots) b += skeleton.nodes[r].memoryBytes;
    return b;
  }

  hlod::Skeleton skeleton;
  std::unique_ptr<hlod::CameraPath> path;
  fs::path out;
};

std::size_t countFiles(const fs::path& dir, const std::string& ext) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ext) ++n;
  return n;
}

}  // namespace

TEST_F(SessionTest, SettledRunWritesOneRecordAndOnePngPerFrameWithNoCoarserNodes) {
  // A budget the whole tiny store fits in even on a loaded machine (CI runs the suites in
  // parallel, under sanitizers too), so the fronts below hlod_0 do not depend on the load.
  auto options = smallOptions();
  options.budgetMs = 1000.0;
  auto session = service::Session::open(tinyStore(), options);
  ASSERT_TRUE(session.ok()) << session.message();
  hlod::PathRunOptions ro;
  ro.fps = 10.0;
  ro.maxFrames = 20;
  ro.mode = hlod::FrameMode::Settled;
  service::FileOutputs fo;
  fo.output = out;
  fo.plots = true;
  auto result = service::runPathToFiles(**session, *path, ro, fo);
  ASSERT_TRUE(result.ok()) << result.message();

  ASSERT_EQ(result->run.framesRendered, 20u);
  ASSERT_EQ(frames(**session).size(), 20u);
  EXPECT_EQ(countFiles(out, ".png"), 20u);
  EXPECT_TRUE(fs::exists(out / "frame_00019.png"));
  for (const auto& f : frames(**session)) {
    EXPECT_EQ(f.coarserNotResident, 0u) << "frame " << f.index;
    EXPECT_GT(f.triangles, 0u);
  }
  // Settled frames draw below hlod_0 once the front is loaded.
  std::uint64_t deeper = 0;
  for (const auto& f : frames(**session))
    for (std::size_t l = 1; l < f.nodesPerLevel.size(); ++l) deeper += f.nodesPerLevel[l];
  EXPECT_GT(deeper, 0u);

  std::ifstream in(out / "stats.json");
  const auto json = nlohmann::json::parse(in, nullptr, false);
  ASSERT_FALSE(json.is_discarded());
  ASSERT_TRUE(json.contains("frames"));
  ASSERT_TRUE(json.contains("summary"));
  EXPECT_EQ(json["frames"].size(), 20u);
  EXPECT_EQ(json["summary"]["frames"].get<int>(), 20);
  EXPECT_TRUE(fs::exists(out / "stats.csv"));
  for (const char* svg : {"levels.svg", "toggles.svg", "frametime.svg"})
    EXPECT_GT(fs::file_size(out / svg), 100u) << svg;
}

// The study's reference within a memory cap: a cap smaller than any node draws the front one
// node a batch, loading and freeing as it goes, and gives the picture of the `full` session that
// holds everything; no cap draws it in one batch.
TEST_F(SessionTest, TheBatchedReferenceDrawsTheFullFrontWithinItsCap) {
  auto options = smallOptions();
  options.selector = "full";
  auto session = service::Session::open(tinyStore(), options);
  ASSERT_TRUE(session.ok()) << session.message();
  const hlod::CameraSample sample = path->sample(0.5, 160.0 / 90.0);
  auto full = (*session)->renderFrame(sample, hlod::FrameMode::Settled);
  ASSERT_TRUE(full.ok()) << full.message();
  const hlod::Image want = (*session)->readback();

  auto opened = hlod::NodeStore::open(tinyStore());
  ASSERT_TRUE(opened.ok()) << opened.message();
  std::shared_ptr<const hlod::NodeSource> source(std::move(*opened));
  renderer::RenderOptions ro;
  ro.width = options.width;
  ro.height = options.height;
  ro.effects = options.effects;  // what the session draws (none declared: flat colours)
  std::uint64_t smallest = ~std::uint64_t(0), largest = 0;
  for (const auto& n : skeleton.nodes) {
    smallest = std::min(smallest, n.memoryBytes - n.textureBytes);
    largest = std::max(largest, n.memoryBytes);
  }
  for (const std::uint64_t cap : {std::uint64_t(0), smallest / 2}) {
    auto ref = service::BatchedReference::create(source, ro, cap, (*session)->context());
    ASSERT_TRUE(ref.ok()) << ref.message();
    for (int repeat = 0; repeat < 2; ++repeat) {
      auto frame = (*ref)->render(sample);
      ASSERT_TRUE(frame.ok()) << frame.message();
      EXPECT_EQ(frame->triangles, full->triangles) << "cap " << cap;
      EXPECT_EQ(frame->nodes, (*session)->driver().lastFront().size()) << "cap " << cap;
      if (cap == 0) {
        EXPECT_EQ(frame->batches, 1u);
      } else {
        // One node a batch, and only the last stays from one frame to the next.
        EXPECT_EQ(frame->batches, frame->nodes);
        EXPECT_EQ(frame->loads, repeat == 0 ? frame->nodes : frame->nodes - 1);
        EXPECT_LE((*ref)->peakBytes(), largest);
      }
      const hlod::Image got = (*ref)->readback();
      ASSERT_EQ(got.pixels.size(), want.pixels.size());
      std::size_t differ = 0;
      for (std::size_t i = 0; i < got.pixels.size(); i += 4)
        differ += !std::equal(&got.pixels[i], &got.pixels[i] + 4, &want.pixels[i]);
      // Batches change the drawing order, which only coplanar ties can tell.
      EXPECT_LE(differ, want.pixels.size() / 4 / 1000) << "cap " << cap;
    }
  }
}

TEST_F(SessionTest, RealtimeRunNeverStallsAndKeepsResidentBytesUnderTheCap) {
  auto o = smallOptions();
  o.memoryCapBytes = rootBytes() * 3;  // room for some of the tree, not all of it
  o.ioMbps = 200.0;                    // loading takes frames: render-while-loading happens
  auto session = service::Session::open(tinyStore(), o);
  ASSERT_TRUE(session.ok()) << session.message();
  hlod::PathRunOptions ro;
  ro.fps = 10.0;
  ro.maxFrames = 20;
  ro.prefetchSeconds = 0.5;
  service::FileOutputs fo;
  fo.statsDir = out;
  auto result = service::runPathToFiles(**session, *path, ro, fo);
  ASSERT_TRUE(result.ok()) << result.message();

  const auto all = frames(**session);
  ASSERT_EQ(all.size(), 20u);
  for (const auto& f : all) {
    EXPECT_EQ(f.stalls, 0u) << "frame " << f.index;
    EXPECT_EQ(f.capBytes, o.memoryCapBytes);
    EXPECT_LE(f.residentBytes, f.capBytes) << "frame " << f.index;
    EXPECT_GT(f.gpuMs, 0.0);
  }
  EXPECT_EQ(result->summary.totalStalls, 0u);
  EXPECT_LE(result->summary.peakOverCap, 1.0);
  EXPECT_TRUE(fs::exists(out / "stats.json"));
  EXPECT_EQ(countFiles(out, ".png"), 0u);  // no image output asked for
}

TEST_F(SessionTest, StartMeasuresVTimeAndTheFeedbackMovesIt) {
  auto session = service::Session::open(tinyStore(), smallOptions());
  ASSERT_TRUE(session.ok()) << session.message();
  // The session starts from this GL's measured speed, not the paper's constant first guess.
  const double measured = (*session)->driver().measuredVTime();
  EXPECT_GT(measured, 0.0);
  EXPECT_NE((*session)->selector().vTime(), hlod::LakhiaParams{}.vTimeInitial);
  EXPECT_DOUBLE_EQ((*session)->selector().vTime(), measured);
  const auto samples = path->sampleAt(10.0, 160.0 / 90.0);
  for (int i = 0; i < 5; ++i)
    ASSERT_TRUE((*session)->renderFrame(samples[i], hlod::FrameMode::Realtime).ok());
  const auto all = frames(**session);
  EXPECT_NE(all.back().vTime, all.front().vTime);
}

// llvmpipe allocates and frees its working memory at every draw. With glibc's defaults the
// freed top of the heap went back to the kernel once a frame's image was read back and freed,
// and every draw of the next frame faulted its pages in again (renderer::keepFreedHeap). A frame
// of an unchanged front, its image read back as every user of a session does, faults in no
// fresh memory.
TEST_F(SessionTest, AFrameOfAnUnchangedFrontFaultsInNoFreshMemory) {
#ifdef HLODR_SANITIZE_BUILD
  GTEST_SKIP() << "the sanitizers' allocator is not glibc's malloc";
#endif
  // glibc's defaults, as a fresh process has them (this one may have raised them already).
  mallopt(M_MMAP_THRESHOLD, 128 * 1024);
  mallopt(M_TRIM_THRESHOLD, 128 * 1024);
  service::SessionOptions o;
  o.width = 640;
  o.height = 360;
  o.selector = "full";
  auto session = service::Session::open(tinyStore(), o);
  ASSERT_TRUE(session.ok()) << session.message();
  const auto sample = path->sampleAt(10.0, 640.0 / 360.0)[0];
  auto faults = [] {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_minflt;
  };
  constexpr int kWarm = 3, kFrames = 10;
  long drawing = 0;  // the faults of the frames alone, their read-backs left out
  std::uint64_t triangles = 0;
  for (int i = 0; i < kWarm + kFrames; ++i) {
    const long before = faults();
    auto r = (*session)->renderFrame(sample, hlod::FrameMode::Settled);
    ASSERT_TRUE(r.ok()) << r.message();
    if (i >= kWarm) drawing += faults() - before;
    triangles = r->triangles;
    EXPECT_FALSE((*session)->readback().pixels.empty());
  }
  EXPECT_GT(triangles, 0u);
  const double perFrame = double(drawing) / kFrames;
  // A few pages for the frame's records; without keepFreedHeap, hundreds.
  EXPECT_LT(perFrame, 32.0) << triangles << " triangles a frame";
}

TEST_F(SessionTest, TwoSessionsRunSideBySideOnOneThread) {
  auto a = service::Session::open(tinyStore(), smallOptions());
  auto b = service::Session::open(tinyStore(), smallOptions());
  ASSERT_TRUE(a.ok()) << a.message();
  ASSERT_TRUE(b.ok()) << b.message();
  const auto samples = path->sampleAt(10.0, 160.0 / 90.0);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE((*a)->renderFrame(samples[i], hlod::FrameMode::Settled).ok());
    ASSERT_TRUE((*b)->renderFrame(samples[samples.size() - 1 - i], hlod::FrameMode::Realtime).ok());
  }
  EXPECT_EQ((*a)->recent().size(), 4u);
  EXPECT_EQ((*b)->recent().size(), 4u);
  // Each readback is its own session's frame: both see the model (not only background).
  for (auto* s : {a->get(), b->get()}) {
    const hlod::Image img = s->readback();
    ASSERT_EQ(img.width, 160);
    const auto* p = img.pixels.data();
    bool varied = false;
    for (std::size_t i = 4; i < img.pixels.size() && !varied; i += 4)
      varied = p[i] != p[0] || p[i + 1] != p[1] || p[i + 2] != p[2];
    EXPECT_TRUE(varied);
  }
}

TEST_F(SessionTest, OpeningSomethingThatIsNotAStoreIsAClearError) {
  fs::create_directories(out);
  auto s = service::Session::open(out, smallOptions());
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("not a node store"), std::string::npos) << s.message();
  auto bad = smallOptions();
  bad.selector = "nope";
  auto t = service::Session::open(tinyStore(), bad);
  ASSERT_FALSE(t.ok());
  EXPECT_NE(t.message().find("unknown selector"), std::string::npos) << t.message();
}

using gltest::runHlodr;

TEST_F(SessionTest, CliWritesAPathAndRendersItToAnMp4) {
  if (std::system("command -v ffmpeg > /dev/null 2>&1") != 0) GTEST_SKIP() << "no ffmpeg";
  fs::create_directories(out);
  const std::string store = tinyStore().string();
  const std::string pathJson = (out / "orbit.json").string();
  auto p = runHlodr("path " + store + " --kind orbit --duration 2 -o " + pathJson);
  ASSERT_EQ(p.status, 0) << p.output;
  ASSERT_TRUE(hlod::CameraPath::read(pathJson).ok());

  const fs::path video = out / "orbit.mp4";
  auto r = runHlodr("render " + store + " --path " + pathJson + " -o " + video.string() +
                    " --size 160x90 --fps 10 --frames 12 --mode settled --budget-ms 10 --plots");
  ASSERT_EQ(r.status, 0) << r.output;
  ASSERT_TRUE(fs::exists(video));
  EXPECT_GT(fs::file_size(video), 0u);
  EXPECT_TRUE(fs::exists(out / "orbit.stats.json"));
  EXPECT_TRUE(fs::exists(out / "orbit.stats.csv"));
  EXPECT_TRUE(fs::exists(out / "orbit.frametime.svg"));
  EXPECT_NE(r.output.find("12 frames"), std::string::npos) << r.output;
}

TEST_F(SessionTest, CliRejectsBadOptionsAndBadPaths) {
  fs::create_directories(out);
  const std::string store = tinyStore().string();
  auto k = runHlodr("path " + store + " --kind spiral -o " + (out / "p.json").string());
  EXPECT_EQ(k.status, 2);
  EXPECT_NE(k.output.find("walk-fly"), std::string::npos) << k.output;

  std::ofstream(out / "bad.json") << "{\"keyframes\": [";
  auto b = runHlodr("render " + store + " --path " + (out / "bad.json").string() + " -o " +
                    (out / "frames").string());
  EXPECT_EQ(b.status, 1);
  EXPECT_NE(b.output.find("bad.json"), std::string::npos) << b.output;

  auto m = runHlodr("render " + store + " --path " + (out / "bad.json").string() + " -o " +
                    (out / "frames").string() + " --mode sometimes");
  EXPECT_EQ(m.status, 2);
  EXPECT_NE(m.output.find("--mode"), std::string::npos) << m.output;

  const std::string run = "render " + store + " --path " + (out / "bad.json").string() + " -o " +
                          (out / "frames").string();
  auto u = runHlodr(run + " --params c_aim=1,c_nope=2");
  EXPECT_EQ(u.status, 2);
  EXPECT_NE(u.output.find("unknown parameter 'c_nope'"), std::string::npos) << u.output;
  EXPECT_NE(u.output.find("c_fillKeep"), std::string::npos) << u.output;  // lists the known ones
  auto q = runHlodr(run + " --io-requests 0");
  EXPECT_EQ(q.status, 2);
  EXPECT_NE(q.output.find("io-requests"), std::string::npos) << q.output;
}
