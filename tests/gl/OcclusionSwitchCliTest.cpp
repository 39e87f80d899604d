// `hlodr switch`: the occlusion-switch across three processes (Manocha sec. 4.2-4.5) on a small
// city at street level. Its frames must equal the unculled frames of the same front.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "RunHlodr.h"
#include "hlod/import/Import.h"

namespace fs = std::filesystem;

namespace {

class OcclusionSwitchCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("hlodr_switch_" + std::to_string(::getpid()));
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  fs::path dir;
};

}  // namespace

TEST_F(OcclusionSwitchCli, FramesEqualTheUnculledFramesAndOnlyDeltasTravel) {
  auto r = gltest::runHlodr("city -o " + path("city") + " --blocks 4 --texture 64 --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  r = gltest::runHlodr("build " + path("city") + " -o " + path("c.hlod") + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  r = gltest::runHlodr("path " + path("c.hlod") + " --kind walk-fly -o " + path("p.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  // The street part of the walk: every leaf is a candidate, the facades hide most of them.
  const std::string frames = " --fps 2 --frames 24 --size 160x90 --quiet ";
  r = gltest::runHlodr("switch " + path("c.hlod") + " --path " + path("p.json") +
                       " --selector full" + frames + "-o " + path("sw"));
  ASSERT_EQ(r.status, 0) << r.output;
  r = gltest::runHlodr("render " + path("c.hlod") + " --path " + path("p.json") +
                       " --selector full --mode settled --occlusion off" + frames + "-o " +
                       path("ref"));
  ASSERT_EQ(r.status, 0) << r.output;

  std::ifstream in(dir / "sw" / "switch.json");
  const auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j["frames"].size(), 24u);
  int culled = 0;
  for (const auto& f : j["frames"]) {
    const int frame = f["frame"];
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.png", frame);
    auto sw = hlod::loadImage(dir / "sw" / name);
    auto ref = hlod::loadImage(dir / "ref" / name);
    ASSERT_TRUE(sw && ref) << name;
    ASSERT_EQ(sw->width, ref->width);
    EXPECT_TRUE(sw->pixels == ref->pixels) << name << " differs from the unculled frame";
    // HC swaps every frame; what it sends is the delta, to OR and to RVG.
    EXPECT_EQ(f["hc"], frame % 2 == 0 ? "A" : "B");
    const std::size_t ids = f["added"].get<std::size_t>() + f["removed"].get<std::size_t>();
    EXPECT_EQ(f["bytes"], 2 * (20 + 72 + 4 * ids));
    EXPECT_EQ(f["fullBytes"], 2 * (20 + 72 + 4 * f["visible"].get<std::size_t>()));
    EXPECT_LE(f["visible"], f["candidates"]);
    culled += f["visible"] < f["candidates"];
  }
  // Frame 0 has no occluders; from then on the facades hide blocks behind them.
  EXPECT_EQ(j["frames"][0]["visible"], j["frames"][0]["candidates"]);
  EXPECT_GT(culled, 12);
  EXPECT_LT(j["summary"]["meanBytes"].get<double>(), j["summary"]["meanFullBytes"].get<double>());
}

TEST_F(OcclusionSwitchCli, ABudgetBoundSelectorOrAMissingStoreIsRefusedClearly) {
  auto r = gltest::runHlodr("switch " + path("none.hlod") + " --path " + path("p.json") + " -o " +
                            path("out") + " --selector lakhia");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("sse or full"), std::string::npos) << r.output;
  r = gltest::runHlodr("switch " + path("none.hlod") + " --path " + path("p.json") + " -o " +
                       path("out"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("none.hlod"), std::string::npos) << r.output;
}
