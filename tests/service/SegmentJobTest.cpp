// A path job split into segments ("segments": N): its segments run as tasks on the job runners
// and are joined into the files, frames and stats of an unsplit job.
#include "ServerFixture.h"

using namespace svctest;

TEST_F(ServerTest, ASettledJobInTwoSegmentsHasTheFramesOfTheUnsplitJob) {
  service::ServerOptions o;
  o.jobRunners = 2;
  start(o);
  // The deterministic setting of docs/cli.md, "Segments": sse, no occlusion culling, settled.
  const json settings = {{"mode", "settled"},  {"selector", "sse"}, {"ssePx", 4},
                         {"occlusion", "off"}, {"video", true},     {"width", 96},
                         {"height", 64}};
  json split = settings;
  split["segments"] = 2;
  const std::string whole = newJob(settings);
  const std::string parts = newJob(split);
  const json a = waitForJob(whole);
  const json b = waitForJob(parts);
  ASSERT_EQ(a["state"], "done") << a.dump();
  ASSERT_EQ(b["state"], "done") << b.dump();
  EXPECT_EQ(b["settings"]["segments"], 2);
  EXPECT_EQ(b["framesDone"], 12);
  EXPECT_EQ(b["summary"]["frames"], 12);
  for (int n = 0; n < 12; ++n) {
    auto fa = client().Get("/api/jobs/" + whole + "/frames/" + std::to_string(n));
    auto fb = client().Get("/api/jobs/" + parts + "/frames/" + std::to_string(n));
    ASSERT_EQ(fa->status, 200);
    ASSERT_EQ(fb->status, 200) << "frame " << n;
    EXPECT_TRUE(fa->body == fb->body) << "frame " << n << " differs";
  }
  const json stats = parse(client().Get("/api/jobs/" + parts + "/stats"));
  ASSERT_EQ(stats["frames"].size(), 12u);
  for (int n = 0; n < 12; ++n) EXPECT_EQ(stats["frames"][n]["index"], n);
  auto video = client().Get("/api/jobs/" + parts + "/video.mp4");
  EXPECT_EQ(video->status, 200);
  EXPECT_GT(video->body.size(), 1000u);
  // The segment files were joined and removed.
  EXPECT_FALSE(fs::exists(jobsFolder() / parts / "segment-0.mp4"));
  EXPECT_TRUE(fs::exists(jobsFolder() / parts / "stats.json"));
}

TEST_F(ServerTest, SegmentsOutOfRangeAreA400) {
  start();
  for (const json& segments : {json(0), json(17), json(13), json("2")}) {
    auto r = post("/api/jobs", {{"scene", "city"},
                                {"path", {{"kind", "orbit"}}},
                                {"fps", 10},
                                {"frames", 12},
                                {"segments", segments}});
    EXPECT_EQ(r->status, 400) << segments << ": " << r->body;
    EXPECT_NE(errorMessage(r).find("segments"), std::string::npos) << r->body;
  }
}
