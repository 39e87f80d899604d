// GET /api/jobs/{id}/trace.json: a path job's frames as Chrome Trace Event JSON, also after a
// restart of the server; the API's 404 for a job that is not there.
#include "ChromeTraceCheck.h"
#include "ServerFixture.h"

using namespace svctest;

namespace {

std::string problems(const json& trace) {
  std::string all;
  for (const auto& p : tracecheck::traceProblems(trace)) all += p + "\n";
  return all;
}

}  // namespace

TEST_F(ServerTest, APathJobServesItsTraceAndKeepsItAcrossARestart) {
  service::ServerOptions o;
  o.jobsDir = jobsFolder();
  start(o);
  auto ghost = client().Get("/api/jobs/j00000000/trace.json");
  EXPECT_EQ(ghost->status, 404);
  EXPECT_EQ(errorCode(ghost), "not_found");

  const std::string id = newJob({{"frames", 3}});
  ASSERT_FALSE(id.empty());
  const json done = waitForJob(id);
  ASSERT_EQ(done["state"], "done");
  EXPECT_EQ(done["outputs"]["trace"], "/api/jobs/" + id + "/trace.json");
  auto r = client().Get("/api/jobs/" + id + "/trace.json");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_NE(r->get_header_value("Content-Type").find("application/json"), std::string::npos);
  const json trace = parse(r);
  EXPECT_EQ(problems(trace), "");
  EXPECT_EQ(tracecheck::frameSlices(trace).size(), 3u);
  EXPECT_EQ(tracecheck::slicesNamed(trace, "readback").size(), 3u);  // the job's JPEG frames
  EXPECT_EQ(tracecheck::slicesNamed(trace, "encode").size(), 3u);

  // The folder's trace.json, served by the restarted server.
  stop();
  start(o);
  auto again = client().Get("/api/jobs/" + id + "/trace.json");
  ASSERT_EQ(again->status, 200) << again->body;
  EXPECT_EQ(problems(parse(again)), "");
  EXPECT_EQ(tracecheck::frameSlices(parse(again)).size(), 3u);
}
