// `--trace FILE` end to end: `hlodr render STORE --path` and `hlodr study` write per-frame
// timing as Chrome Trace Event JSON that passes the format's checks (ChromeTraceCheck.h).
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "../service/ChromeTraceCheck.h"
#include "CachedStore.h"
#include "RunHlodr.h"

namespace fs = std::filesystem;

namespace {

class TraceCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("hlodr_trace_" + std::to_string(::getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
    // A city of one block and its store, built once for the binary: a few frames of it render
    // in well under a second.
    store = gltest::cachedStore("trace-city", [](const fs::path& d) {
      fs::create_directories(d);
      const std::string city = (d / "city").string();
      return gltest::runHlodr("city -o " + city + " --blocks 1 --texture 64 --quiet").status == 0 &&
             gltest::runHlodr("build " + city + " -o " + (d / "c.hlod").string() + " --quiet")
                     .status == 0;
    });
    ASSERT_FALSE(store.empty());
    store /= "c.hlod";
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  static nlohmann::json read(const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in, nullptr, false);
  }
  static std::string problems(const nlohmann::json& trace) {
    std::string all;
    for (const auto& p : tracecheck::traceProblems(trace)) all += p + "\n";
    return all;
  }
  fs::path dir, store;
};

TEST_F(TraceCli, APathRunWritesATraceOfEveryFrameWithItsStepsNested) {
  auto r = gltest::runHlodr("path " + store.string() + " --kind orbit -o " + path("p.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  r = gltest::runHlodr("render " + store.string() + " --path " + path("p.json") +
                       " --frames 4 --fps 10 --size 160x90 --quiet -o " + path("out") +
                       " --trace " + path("t.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("trace: " + path("t.json")), std::string::npos) << r.output;
  const nlohmann::json trace = read(dir / "t.json");
  ASSERT_TRUE(trace.is_object()) << "not JSON";
  EXPECT_EQ(problems(trace), "");
  const auto frames = tracecheck::frameSlices(trace);
  ASSERT_EQ(frames.size(), 4u);
  // Each frame selected, drew its geometry, was read back and encoded (the PNG sequence).
  for (const char* step : {"select", "draw", "geometry", "readback", "encode"})
    EXPECT_EQ(tracecheck::slicesNamed(trace, step).size(), 4u) << step;
  // On one steady clock: the frames follow each other in time.
  for (std::size_t i = 1; i < frames.size(); ++i) EXPECT_GE(frames[i].ts, frames[i - 1].end());
  EXPECT_EQ(trace["otherData"]["framesWithoutTimeline"], 0);
  EXPECT_EQ(trace["otherData"]["runs"][0]["settings"]["mode"], "realtime");
}

TEST_F(TraceCli, TraceWithoutAPathIsAUsageError) {
  const auto r = gltest::runHlodr("render " + store.string() + " -o " + path("f.png") +
                                  " --trace " + path("t.json") + " --quiet");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--trace is for a path"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "t.json"));
}

TEST_F(TraceCli, AStudyWritesAProcessPerRun) {
  const auto r = gltest::runHlodr("study " + store.string() +
                                  " --kind orbit --frames 2 --budgets 33 --selectors lakhia "
                                  "--sse-px 4 --strips 0 --size 160x90 --quiet -o " +
                                  path("st") + " --trace " + path("st.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json trace = read(dir / "st.json");
  ASSERT_TRUE(trace.is_object()) << "not JSON";
  EXPECT_EQ(problems(trace), "");
  std::set<int> pids;
  for (const auto& e : trace["traceEvents"])
    if (e["name"] == "process_name") pids.insert(e["pid"].get<int>());
  EXPECT_EQ(pids.size(), trace["otherData"]["runs"].size());
  EXPECT_GE(pids.size(), 1u);
  EXPECT_GE(tracecheck::frameSlices(trace).size(), 2u);
  EXPECT_GE(tracecheck::slicesNamed(trace, "readback").size(), 2u);  // the studied frames
}

}  // namespace
