// Jobs outlive the server: each keeps its record beside its outputs, a server started on the
// same folder lists them again, and finished jobs expire by the documented rule.
#include "ServerFixture.h"

using namespace svctest;

namespace {

// Rewrites the createdAt of a job's record (a job made days ago).
void backdate(const fs::path& dir, const std::string& createdAt) {
  std::ifstream in(dir / "job.json");
  json record = json::parse(in, nullptr, false);
  ASSERT_TRUE(record.is_object());
  record["job"]["createdAt"] = createdAt;
  std::ofstream(dir / "job.json") << record.dump();
}

}  // namespace

TEST_F(ServerTest, AFinishedJobIsListedAgainAfterARestartWithItsOutputs) {
  service::ServerOptions o;
  o.jobsDir = jobsFolder();
  start(o);
  const std::string done = newJob({{"video", true}});
  ASSERT_FALSE(done.empty());
  const json before = waitForJob(done);
  ASSERT_EQ(before["state"], "done");
  // A long one, running when the server stops (as on SIGTERM): it is cancelled and says so.
  const std::string running = newJob({{"frames", 3000}, {"fps", 30}});
  waitForFrames(running, 2);
  stop();

  start(o);
  auto list = client().Get("/api/jobs");
  ASSERT_EQ(list->status, 200);
  const json jobs = parse(list)["jobs"];
  ASSERT_EQ(jobs.size(), 2u) << list->body;
  EXPECT_EQ(jobs[0]["id"], running);  // newest first
  EXPECT_EQ(jobs[0]["state"], "cancelled");
  EXPECT_EQ(jobs[1]["id"], done);
  EXPECT_EQ(jobs[1]["state"], "done");
  EXPECT_EQ(jobs[1]["framesDone"], before["framesDone"]);
  EXPECT_EQ(jobs[1]["summary"], before["summary"]);
  auto frame = client().Get("/api/jobs/" + done + "/frames/11");
  EXPECT_EQ(frame->status, 200);
  EXPECT_TRUE(isJpeg(frame->body));
  EXPECT_EQ(parse(client().Get("/api/jobs/" + done + "/stats"))["frames"].size(), 12u);
  EXPECT_EQ(client().Get("/api/jobs/" + done + "/stats.csv")->body.rfind("index,", 0), 0u);
  auto video = client().Get("/api/jobs/" + done + "/video.mp4");
  EXPECT_EQ(video->status, 200);
  EXPECT_NE(video->body.find("ftyp"), std::string::npos);
  // Its event stream replays the frames and ends.
  const std::string events = client().Get("/api/jobs/" + done + "/events")->body;
  std::size_t frames = 0;
  for (std::size_t at = 0; (at = events.find("event: frame", at)) != std::string::npos; ++at)
    ++frames;
  EXPECT_EQ(frames, 12u);
  EXPECT_NE(events.find("event: end"), std::string::npos);
  // And a restored job is removed with its folder like any other.
  EXPECT_EQ(client().Delete("/api/jobs/" + done)->status, 204);
  EXPECT_FALSE(fs::exists(o.jobsDir / done));
}

TEST_F(ServerTest, AStudyIsListedAgainAfterARestartWithItsReport) {
  service::ServerOptions o;
  o.jobsDir = jobsFolder();
  start(o);
  auto r = post("/api/studies", {{"scene", "city"},
                                 {"path", {{"kind", "orbit"}}},
                                 {"frames", 1},
                                 {"budgets", {33}},
                                 {"selectors", {"lakhia"}},
                                 {"width", 96},
                                 {"height", 64},
                                 {"strips", 0}});
  ASSERT_EQ(r->status, 202) << r->body;
  const std::string id = parse(r)["id"];
  ASSERT_EQ(waitForJob(id, "studies")["state"], "done");
  stop();
  start(o);
  const json study = parse(client().Get("/api/studies/" + id));
  EXPECT_EQ(study["state"], "done") << study.dump();
  EXPECT_EQ(study["kind"], "study");
  EXPECT_EQ(client().Get("/api/studies/" + id + "/report/index.html")->status, 200);
}

// A record left as "running" (the server was killed, it could not write more) shows the job as
// failed, and says why.
TEST_F(ServerTest, AJobInterruptedWithoutAWordShowsAsFailed) {
  service::ServerOptions o;
  o.jobsDir = jobsFolder();
  start(o);
  const std::string id = newJob();
  waitForJob(id);
  stop();
  {
    std::ifstream in(o.jobsDir / id / "job.json");
    json record = json::parse(in, nullptr, false);
    record["job"]["state"] = "running";
    std::ofstream(o.jobsDir / id / "job.json") << record.dump();
  }
  start(o);
  const json job = parse(client().Get("/api/jobs/" + id));
  EXPECT_EQ(job["state"], "failed");
  EXPECT_NE(job["error"].get<std::string>().find("interrupted"), std::string::npos) << job.dump();
  EXPECT_TRUE(job["finished"].get<bool>());
}

// --keep-jobs-days: finished jobs older than that go with their folders at the next start (and
// while it runs); the young ones stay. Folders without a record that old go too.
TEST_F(ServerTest, FinishedJobsOlderThanTheKeepDaysAreRemovedWithTheirFolders) {
  service::ServerOptions o;
  o.jobsDir = jobsFolder();
  o.keepJobsDays = 7;
  start(o);
  const std::string old = newJob(), young = newJob();
  waitForJob(old);
  waitForJob(young);
  stop();
  backdate(o.jobsDir / old, "2020-01-01T00:00:00Z");
  fs::create_directories(o.jobsDir / "j0123abcd" / "frames");  // no record: an older server's
  fs::last_write_time(o.jobsDir / "j0123abcd",
                      fs::file_time_type::clock::now() - std::chrono::hours(24 * 30));
  fs::create_directories(o.jobsDir / "notes");  // not a job's: left alone
  start(o);
  EXPECT_EQ(client().Get("/api/jobs/" + old)->status, 404);
  EXPECT_FALSE(fs::exists(o.jobsDir / old));
  EXPECT_EQ(client().Get("/api/jobs/" + young)->status, 200);
  EXPECT_TRUE(fs::exists(o.jobsDir / young));
  EXPECT_FALSE(fs::exists(o.jobsDir / "j0123abcd"));
  EXPECT_TRUE(fs::exists(o.jobsDir / "notes"));
}

// --jobs-max-mb: past the cap the oldest finished jobs go until the rest fit.
TEST_F(ServerTest, PastTheByteCapTheOldestFinishedJobsAreRemoved) {
  service::ServerOptions o;
  o.jobsDir = jobsFolder();
  start(o);
  std::vector<std::string> ids;
  for (int i = 0; i < 3; ++i) {
    ids.push_back(newJob());
    waitForJob(ids.back());
  }
  stop();
  std::uint64_t newest = 0;
  for (const auto& e : fs::recursive_directory_iterator(o.jobsDir / ids[2]))
    if (e.is_regular_file()) newest += e.file_size();
  o.jobsMaxBytes = newest + newest / 2;  // room for one job and a half: the two oldest go
  start(o);
  EXPECT_EQ(client().Get("/api/jobs/" + ids[0])->status, 404);
  EXPECT_EQ(client().Get("/api/jobs/" + ids[1])->status, 404);
  EXPECT_EQ(client().Get("/api/jobs/" + ids[2])->status, 200);
  EXPECT_FALSE(fs::exists(o.jobsDir / ids[0]));
  EXPECT_TRUE(fs::exists(o.jobsDir / ids[2]));
}
