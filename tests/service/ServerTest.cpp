// `hlodr serve` in-process on an ephemeral loopback port, driven by HTTP clients: every
// endpoint, the bad-input cases of docs/api.md, concurrency and the limits, event streams
// followed to the end and dropped mid-way.
#include "ServerFixture.h"

using namespace svctest;

namespace {

// The process's folders (the city copied in, every test's jobs, the page) go when it ends: each
// run left them behind in the temporary folder.
class RemoveTestFolders : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dataDir(), ec);
    fs::remove_all(webDir(), ec);
  }
};
[[maybe_unused]] const ::testing::Environment* const kRemoveTestFolders =
    ::testing::AddGlobalTestEnvironment(new RemoveTestFolders);

}  // namespace

TEST_F(ServerTest, HealthAndScenesListTheStoresOfTheDataFolderOnly) {
  start();
  auto h = client().Get("/healthz");
  ASSERT_TRUE(h);
  EXPECT_EQ(h->status, 200);
  EXPECT_EQ(parse(h)["status"], "ok");
  auto s = client().Get("/api/scenes");
  ASSERT_TRUE(s);
  ASSERT_EQ(s->status, 200);
  const json scenes = parse(s)["scenes"];
  ASSERT_EQ(scenes.size(), 1u) << s->body;  // not the folder without a store, not the broken one
  EXPECT_EQ(scenes[0]["id"], "city");
  EXPECT_GT(scenes[0]["nodes"].get<int>(), 2);
  EXPECT_EQ(scenes[0]["defaultCamera"]["position"].size(), 3u);
  EXPECT_NE(log.find("broken skipped"), std::string::npos) << log;
  auto d = client().Get("/api/scenes/city");
  ASSERT_TRUE(d);
  EXPECT_EQ(d->status, 200);
  EXPECT_GT(parse(d)["levelsDetail"].size(), 1u);
  auto missing = client().Get("/api/scenes/nope");
  EXPECT_EQ(missing->status, 404);
  EXPECT_EQ(errorCode(missing), "not_found");
}

TEST_F(ServerTest, RenderAnswersAnImageWithServerTimingAndStatsHeaders) {
  start();
  auto r = post("/api/render", {{"scene", "city"}, {"width", 320}, {"height", 200}});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "image/jpeg");
  EXPECT_TRUE(isJpeg(r->body));
  const std::string timing = r->get_header_value("Server-Timing");
  for (const char* part : {"queue;dur=", "select;dur=", "upload;dur=", "draw;dur=", "readback;dur=",
                           "encode;dur=", "total;dur="})
    EXPECT_NE(timing.find(part), std::string::npos) << timing;
  const json stats = json::parse(r->get_header_value("X-Hlodr-Stats"), nullptr, false);
  ASSERT_TRUE(stats.is_object());
  EXPECT_GT(stats["triangles"].get<long long>(), 0);
  EXPECT_EQ(stats["targetMs"].get<double>(), 33.0);
  auto png =
      post("/api/render", {{"scene", "city"}, {"format", "png"}, {"width", 64}, {"height", 48}});
  ASSERT_TRUE(png);
  ASSERT_EQ(png->status, 200);
  EXPECT_EQ(png->get_header_value("Content-Type"), "image/png");
  EXPECT_TRUE(isPng(png->body));
}

TEST_F(ServerTest, RenderTakesASceneInlineOrAsAFileAndRunsOnlyItsPasses) {
  start();
  std::ofstream(dataDir() / "sunny.json")
      << R"({"store": "../somewhere/city.hlod", "background": {"sky": {}},
            "effects": {"shading": "lambert", "sun": true, "ssao": true}})";
  auto statsOf = [](const Reply& r) {
    return json::parse(r->get_header_value("X-Hlodr-Stats"), nullptr, false);
  };
  auto plain = post("/api/render", {{"scene", "city"}, {"width", 96}, {"height", 64}});
  ASSERT_TRUE(plain);
  ASSERT_EQ(plain->status, 200) << plain->body;
  const json p = statsOf(plain);
  EXPECT_EQ(p["ssaoMs"].get<double>(), 0.0);  // not declared: the pass does not run
  EXPECT_EQ(p["skyMs"].get<double>(), 0.0);
  EXPECT_GT(p["geometryMs"].get<double>(), 0.0);
  auto file = post("/api/render", {{"scene", "sunny.json"}, {"width", 96}, {"height", 64}});
  ASSERT_TRUE(file);
  ASSERT_EQ(file->status, 200) << file->body;
  const json f = statsOf(file);
  EXPECT_GT(f["ssaoMs"].get<double>() + f["ssaoBlurMs"].get<double>(), 0.0);
  EXPECT_NE(file->body, plain->body);
  const json inlined = {{"store", "city"}, {"effects", {{"outline", true}}}};
  auto in = post("/api/render", {{"scene", inlined}, {"width", 96}, {"height", 64}});
  ASSERT_TRUE(in);
  ASSERT_EQ(in->status, 200) << in->body;
  EXPECT_EQ(statsOf(in)["ssaoMs"].get<double>(), 0.0);
  auto bad = post("/api/render", {{"scene", {{"store", "city"}, {"effects", {{"bloom", true}}}}}});
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  EXPECT_NE(bad->body.find("scene.effects.bloom: unknown effect (known: textures"),
            std::string::npos)
      << bad->body;
  auto missing = post("/api/render", {{"scene", "cloudy.json"}});
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
  auto outside = post("/api/render", {{"scene", "../x.json"}});
  ASSERT_TRUE(outside);
  EXPECT_EQ(outside->status, 400);
}

// A scene file's camera: listed with its effects for the page, the camera a session starts
// from, and where an orbit job starts (its first frame is the scene camera's view, not the
// store's framing).
TEST_F(ServerTest, ASceneFilesCameraStartsItsSessionsAndItsOrbitJobs) {
  start();
  auto listed = client().Get("/api/scenes");
  ASSERT_TRUE(listed);
  const json city = parse(listed)["scenes"][0];
  // From the other side of the model, lower and nearer than the store's framing.
  const json lo = city["bounds"]["min"], hi = city["bounds"]["max"];
  const double cx = (lo[0].get<double>() + hi[0].get<double>()) / 2;
  const double cy = (lo[1].get<double>() + hi[1].get<double>()) / 2;
  const double span = hi[0].get<double>() - lo[0].get<double>();
  const json camera = {{"position", {cx + 0.6 * span, cy + 0.5 * span, 0.3 * span}},
                       {"target", {cx, cy, 0}},
                       {"fov", 40}};
  const json effects = {{"shading", "lambert"}, {"sun", true}};
  std::ofstream(dataDir() / "corner.json")
      << json{{"store", "city.hlod"}, {"camera", camera}, {"effects", effects}}.dump();
  std::ofstream(dataDir() / "path.json") << R"({"keyframes": []})";  // not a scene: not listed
  listed = client().Get("/api/scenes");
  // Other tests of this process may have left scene files of their own.
  json corner, notAScene;
  const json listing = parse(listed);
  for (const json& f : listing["scenes"][0]["sceneFiles"]) {
    if (f["name"] == "corner.json") corner = f;
    if (f["name"] == "path.json") notAScene = f;
  }
  EXPECT_EQ(corner["effects"], json({"lambert", "sun"})) << listed->body;
  EXPECT_TRUE(notAScene.is_null()) << listed->body;

  auto session = post("/api/sessions", {{"scene", "corner.json"}, {"width", 96}, {"height", 64}});
  ASSERT_TRUE(session);
  ASSERT_EQ(session->status, 201) << session->body;
  const json start = parse(session)["defaultCamera"];
  for (int i = 0; i < 3; ++i)
    EXPECT_DOUBLE_EQ(start["position"][i].get<double>(), camera["position"][i].get<double>());
  EXPECT_DOUBLE_EQ(start["fov"].get<double>(), 40.0);

  // The job's first frame against two renders at full detail: the scene file's camera and the
  // store's framing (the same effects inline, no camera).
  auto imageOf = [](const std::string& bytes, const char* name) {
    const fs::path file = dataDir() / name;
    std::ofstream(file, std::ios::binary) << bytes;
    auto img = hlod::loadImage(file);
    EXPECT_TRUE(img) << img.message();
    return img ? *img : hlod::Image{};
  };
  auto render = [&](const json& scene) {
    auto r = post(
        "/api/render",
        {{"scene", scene}, {"width", 96}, {"height", 64}, {"selector", "full"}, {"format", "png"}});
    EXPECT_TRUE(r && r->status == 200) << (r ? r->body : "no answer");
    return r ? imageOf(r->body, "render.png") : hlod::Image{};
  };
  const hlod::Image atScene = render("corner.json");
  const hlod::Image framed = render(json{{"store", "city"}, {"effects", effects}});
  const std::string id = newJob({{"scene", "corner.json"},
                                 {"frames", 1},
                                 {"mode", "settled"},
                                 {"selector", "full"},
                                 {"width", 96},
                                 {"height", 64}});
  const json done = waitForJob(id);
  ASSERT_EQ(done["state"], "done");
  EXPECT_EQ(done["settings"]["sceneFile"], "corner.json");  // which file the job ran
  EXPECT_EQ(done["settings"]["effects"], json({"lambert", "sun"}));
  auto frame = client().Get("/api/jobs/" + id + "/frames/0");
  ASSERT_TRUE(frame);
  ASSERT_EQ(frame->status, 200);
  const hlod::Image first = imageOf(frame->body, "frame0.jpg");
  auto meanAbs = [](const hlod::Image& a, const hlod::Image& b) {
    EXPECT_EQ(a.pixels.size(), b.pixels.size());
    double sum = 0;
    for (std::size_t i = 0; i < std::min(a.pixels.size(), b.pixels.size()); ++i)
      sum += std::abs(int(a.pixels[i]) - int(b.pixels[i]));
    return sum / double(std::max<std::size_t>(1, a.pixels.size()));
  };
  const double toScene = meanAbs(first, atScene), toFramed = meanAbs(first, framed);
  EXPECT_LT(toScene, 4.0);  // JPEG at quality 85
  EXPECT_GT(toFramed, 3.0 * toScene) << toScene << " against " << toFramed;
}

TEST_F(ServerTest, BadInputIsA4xxThatNamesTheFieldAndTheServerKeepsServing) {
  start();
  struct Case {
    std::string path, body, contentType;
    int status;
    std::string code, mentions;
  };
  const std::string deep = std::string(20000, '[') + std::string(20000, ']');
  const std::vector<Case> cases = {
      {"/api/render", "{not json", "application/json", 400, "bad_request", "not valid JSON"},
      {"/api/render", "[1,2]", "application/json", 400, "bad_request", "JSON object"},
      {"/api/render", R"({"scene":"city","width":0})", "application/json", 400, "bad_request",
       "width"},
      {"/api/render", R"({"scene":"city","height":99999})", "application/json", 400, "bad_request",
       "height"},
      {"/api/render", R"({"scene":"city","budgetMs":-1})", "application/json", 400, "bad_request",
       "budgetMs"},
      {"/api/render", R"({"scene":"city","selector":"best"})", "application/json", 400,
       "bad_request", "selector"},
      {"/api/render", R"({"scene":"city","widht":100})", "application/json", 400, "bad_request",
       "widht"},
      {"/api/render", R"({"scene":"city","camera":{"position":[0,0,"x"]}})", "application/json",
       400, "bad_request", "camera.position"},
      {"/api/render", R"({"scene":"city","camera":{"position":[1,1,1],"target":[1,1,1]}})",
       "application/json", 400, "bad_request", "camera"},
      {"/api/render", R"({"scene":"city","quality":0})", "application/json", 400, "bad_request",
       "quality"},
      {"/api/render", "{\"scene\":\"city\",\"width\":1e400}", "application/json", 400,
       "bad_request", ""},
      {"/api/render", R"({"scene":"../../etc/passwd"})", "application/json", 404, "not_found", ""},
      {"/api/render", R"({"scene":"nope"})", "application/json", 404, "not_found", "nope"},
      {"/api/render", R"({"width":100})", "application/json", 400, "bad_request", "scene"},
      {"/api/render", R"({"scene":"city"})", "text/plain", 415, "unsupported_media_type", ""},
      {"/api/render", deep, "application/json", 400, "bad_request", "nested"},
      {"/api/sessions", R"({"scene":"city","memoryMb":-5})", "application/json", 400, "bad_request",
       "memoryMb"},
      {"/api/sessions", R"({"scene":"city","occlusion":"sometimes"})", "application/json", 400,
       "bad_request", "occlusion"},
      {"/api/sessions", R"({"scene":"city","gpuMb":-1})", "application/json", 400, "bad_request",
       "gpuMb"},
      {"/api/render", R"({"scene":"city","gpuMb":64})", "application/json", 400, "bad_request",
       "gpuMb"},
      {"/api/jobs", R"({"scene":"city"})", "application/json", 400, "bad_request", "path"},
      {"/api/jobs", R"({"scene":"city","path":{"kind":"spiral"}})", "application/json", 400,
       "bad_request", "path.kind"},
      {"/api/jobs", R"({"scene":"city","path":{"keyframes":[{"time":0}]}})", "application/json",
       400, "bad_request", "path"},
      {"/api/jobs", R"({"scene":"city","path":{"kind":"orbit"},"fps":30000})", "application/json",
       400, "bad_request", "fps"},
      {"/api/jobs", R"({"scene":"city","path":{"kind":"orbit","duration":3000},"fps":240})",
       "application/json", 400, "bad_request", "limit"},
      {"/api/jobs", R"({"scene":"city","path":{"kind":"orbit"},"video":true,"width":161})",
       "application/json", 400, "bad_request", "even"},
  };
  for (const auto& c : cases) {
    auto r = client().Post(c.path, c.body, c.contentType);
    ASSERT_TRUE(r) << c.path << " " << c.body.substr(0, 60);
    EXPECT_EQ(r->status, c.status) << c.body.substr(0, 60) << " -> " << r->body;
    EXPECT_EQ(errorCode(r), c.code) << c.body.substr(0, 60) << " -> " << r->body;
    EXPECT_NE(errorMessage(r).find(c.mentions), std::string::npos)
        << c.body.substr(0, 60) << " -> " << r->body;
  }
  // A body over 1 MiB, an unknown route, a frame of an unknown session.
  auto big = client().Post("/api/render", std::string(2 << 20, ' '), "application/json");
  ASSERT_TRUE(big);
  EXPECT_EQ(big->status, 413);
  EXPECT_EQ(errorCode(big), "too_large");
  auto route = client().Get("/api/teapot");
  EXPECT_EQ(route->status, 404);
  EXPECT_EQ(errorCode(route), "not_found");
  auto ghost = post("/api/sessions/s00000000/frame", json::object());
  EXPECT_EQ(ghost->status, 404);
  EXPECT_EQ(client().Get("/api/jobs/j00000000")->status, 404);
  EXPECT_EQ(client().Get("/api/jobs/x/frames/0")->status, 404);
  // Still serving.
  auto ok = post("/api/render", {{"scene", "city"}, {"width", 32}, {"height", 32}});
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->status, 200);
}

TEST_F(ServerTest, ASessionKeepsItsCameraAndItsStatisticsAndIsClosedByDelete) {
  start();
  const std::string id = newSession({{"budgetMs", 20}});
  ASSERT_FALSE(id.empty());
  const json camera = {{"position", {100, -60, 40}}, {"target", {100, 50, 5}}};
  std::vector<std::string> bodies;
  for (int i = 0; i < 4; ++i) {
    auto r = post("/api/sessions/" + id + "/frame",
                  {{"camera", camera}, {"still", i == 3}, {"format", "png"}});
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    EXPECT_TRUE(isPng(r->body));
    const json stats = json::parse(r->get_header_value("X-Hlodr-Stats"));
    EXPECT_EQ(stats["session"], id);
    EXPECT_EQ(stats["index"].get<int>(), i);  // one session: frames numbered in order
    EXPECT_EQ(stats["targetMs"].get<double>(), 20.0);
    bodies.push_back(r->body);
  }
  // No camera: the session's last one again.
  auto again = post("/api/sessions/" + id + "/frame", {{"still", true}, {"format", "png"}});
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200);
  auto info = client().Get("/api/sessions/" + id);
  ASSERT_TRUE(info);
  ASSERT_EQ(info->status, 200);
  const json j = parse(info);
  EXPECT_EQ(j["frames"].get<int>(), 5);
  EXPECT_EQ(j["recent"].size(), 5u);
  EXPECT_EQ(j["camera"]["position"][0].get<double>(), 100.0);
  auto del = client().Delete("/api/sessions/" + id);
  EXPECT_EQ(del->status, 204);
  EXPECT_EQ(post("/api/sessions/" + id + "/frame", json::object())->status, 404);
  EXPECT_EQ(client().Delete("/api/sessions/" + id)->status, 404);
}

// On a clock of the test's own: no sleeps, and the session's idle time is exactly what the
// test says.
TEST_F(ServerTest, IdleSessionsExpireAndTheSessionLimitAnswers429) {
  // The idle time's clock stands still but where the test moves it: how long the requests take
  // on a loaded machine counts for nothing (the background expiry reads the same clock).
  auto offset = std::make_shared<std::atomic<long long>>(0);  // seconds the test moved it on
  const auto base = std::chrono::steady_clock::now();
  service::ServerOptions o;
  o.sessionIdleSeconds = 60;
  o.maxSessions = 2;
  o.clock = [offset, base] { return base + std::chrono::seconds(offset->load()); };
  start(o);
  const std::string a = newSession(), b = newSession();
  auto third = post("/api/sessions", {{"scene", "city"}});
  EXPECT_EQ(third->status, 429);
  EXPECT_EQ(errorCode(third), "too_many_sessions");
  EXPECT_EQ(third->get_header_value("Retry-After"), "1");
  *offset = 30;  // half the idle time: both stay
  server->closeIdleSessions();
  EXPECT_EQ(client().Get("/api/sessions/" + a)->status, 200);
  EXPECT_EQ(post("/api/sessions/" + b + "/frame", json::object())->status, 200);  // b is used
  *offset = 60;  // a idle exactly the limit, not longer: it stays
  EXPECT_EQ(server->closeIdleSessions(), 0u);
  EXPECT_EQ(client().Get("/api/sessions/" + a)->status, 200);
  *offset = 61;  // a idle 61 s, b 31 s
  server->closeIdleSessions();
  EXPECT_EQ(client().Get("/api/sessions/" + a)->status, 404);
  EXPECT_EQ(client().Get("/api/sessions/" + b)->status, 200);
  *offset = 100;
  server->closeIdleSessions();
  EXPECT_EQ(client().Get("/api/sessions/" + b)->status, 404);
  EXPECT_FALSE(newSession().empty());  // room again
}

// The admission rule (serve --admission): sessions that asked for frames within the last second
// share one budget, or queue for it, on whatever worker each lives. On the test's clock, as above.
TEST_F(ServerTest, SessionsAskingAtOnceShareOneBudgetOrQueueForIt) {
  for (const bool share : {true, false}) {
    SCOPED_TRACE(share ? "share" : "queue");
    auto offset = std::make_shared<std::atomic<long long>>(0);
    const auto base = std::chrono::steady_clock::now();
    service::ServerOptions o;
    o.workers = 2;
    o.shareBudget = share;
    o.clock = [offset, base] { return base + std::chrono::seconds(offset->load()); };
    start(o);
    const std::string a = newSession({{"budgetMs", 30}}), b = newSession({{"budgetMs", 30}});
    const auto frameStats = [&](const std::string& id) {
      auto r = post("/api/sessions/" + id + "/frame", json::object());
      EXPECT_TRUE(r && r->status == 200);
      return r ? json::parse(r->get_header_value("X-Hlodr-Stats"), nullptr, false) : json();
    };
    const auto expectShare = [&](const json& stats, int k) {
      EXPECT_EQ(stats["budgetMs"].get<double>(), 30.0);
      EXPECT_EQ(stats["sharedBy"].get<int>(), share ? k : 1);
      EXPECT_DOUBLE_EQ(stats["targetMs"].get<double>(), share ? 30.0 / k : 30.0);
    };
    expectShare(frameStats(a), 1);  // b has not asked yet
    expectShare(frameStats(b), 2);
    expectShare(frameStats(a), 2);
    const auto askingGauge = [&] {
      const std::string text = client().Get("/metrics")->body;
      const auto at = text.find("\nhlodr_sessions_asking ");
      return at == std::string::npos ? -1 : std::stoi(text.substr(at + 23));
    };
    EXPECT_EQ(askingGauge(), 2);
    *offset = 2;  // both asked 2 s ago: a asks alone again
    EXPECT_EQ(askingGauge(), 0);
    expectShare(frameStats(a), 1);
    EXPECT_EQ(askingGauge(), 1);
    stop();
  }
}

TEST_F(ServerTest, AJobRunsToTheEndWithFramesStatsVideoAndAnEventStreamThatReplays) {
  start();
  const std::string id = newJob({{"video", true}});
  ASSERT_FALSE(id.empty());
  // Follow the stream to its end: every frame once, then the end event.
  int frames = 0, ends = 0;
  std::vector<int> indices;
  std::string buffer;
  auto r = client().Get("/api/jobs/" + id + "/events", [&](const char* data, std::size_t n) {
    buffer.append(data, n);
    std::size_t at;
    while ((at = buffer.find("\n\n")) != std::string::npos) {
      const std::string ev = buffer.substr(0, at);
      buffer.erase(0, at + 2);
      if (ev.rfind("event: frame", 0) == 0) {
        ++frames;
        indices.push_back(json::parse(ev.substr(ev.find("data: ") + 6))["index"]);
      }
      if (ev.rfind("event: end", 0) == 0) ++ends;
    }
    return true;
  });
  ASSERT_TRUE(r);
  EXPECT_EQ(r->get_header_value("Content-Type"), "text/event-stream");
  EXPECT_EQ(frames, 12);
  EXPECT_EQ(ends, 1);
  for (int i = 0; i < int(indices.size()); ++i) EXPECT_EQ(indices[i], i);
  const json job = waitForJob(id);
  EXPECT_EQ(job["state"], "done");
  EXPECT_EQ(job["framesDone"].get<int>(), 12);
  EXPECT_EQ(job["summary"]["frames"].get<int>(), 12);
  // Outputs.
  auto f = client().Get("/api/jobs/" + id + "/frames/11");
  ASSERT_TRUE(f);
  EXPECT_EQ(f->status, 200);
  EXPECT_TRUE(isJpeg(f->body));
  EXPECT_EQ(client().Get("/api/jobs/" + id + "/frames/12")->status, 404);
  auto csv = client().Get("/api/jobs/" + id + "/stats.csv");
  ASSERT_TRUE(csv);
  EXPECT_EQ(csv->body.rfind("index,time,targetMs", 0), 0u);
  EXPECT_EQ(std::count(csv->body.begin(), csv->body.end(), '\n'), 13);
  auto csv2 = client().Get("/api/jobs/" + id + "/stats?format=csv");
  EXPECT_EQ(csv2->body, csv->body);
  auto stats = client().Get("/api/jobs/" + id + "/stats");
  EXPECT_EQ(parse(stats)["frames"].size(), 12u);
  auto video = client().Get("/api/jobs/" + id + "/video.mp4");
  ASSERT_TRUE(video);
  EXPECT_EQ(video->status, 200);
  EXPECT_EQ(video->get_header_value("Content-Type"), "video/mp4");
  EXPECT_NE(video->body.find("ftyp"), std::string::npos);
  // A client joining after the end gets the whole replay.
  auto late = client().Get("/api/jobs/" + id + "/events");
  ASSERT_TRUE(late);
  std::size_t n = 0;
  for (std::size_t at = 0; (at = late->body.find("event: frame", at)) != std::string::npos; ++at)
    ++n;
  EXPECT_EQ(n, 12u);
  // The list, and removal of a finished job.
  auto list = client().Get("/api/jobs");
  EXPECT_EQ(parse(list)["jobs"][0]["id"], id);
  EXPECT_EQ(client().Delete("/api/jobs/" + id)->status, 204);
  EXPECT_EQ(client().Get("/api/jobs/" + id)->status, 404);
}

TEST_F(ServerTest, CancellingARunningJobStopsItAndKeepsWhatItRendered) {
  start();
  const std::string id = newJob({{"frames", 3000}, {"fps", 30}, {"video", true}});
  ASSERT_FALSE(id.empty());
  for (int i = 0; i < 300; ++i) {
    if (parse(client().Get("/api/jobs/" + id))["framesDone"].get<int>() > 3) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  auto v = client().Get("/api/jobs/" + id + "/video.mp4");
  EXPECT_EQ(v->status, 409);  // not done yet
  EXPECT_EQ(errorCode(v), "conflict");
  auto c = client().Delete("/api/jobs/" + id);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->status, 200);
  const json job = waitForJob(id);
  EXPECT_EQ(job["state"], "cancelled");
  const int done = job["framesDone"].get<int>();
  EXPECT_GT(done, 3);
  EXPECT_LT(done, 3000);
  auto stats = client().Get("/api/jobs/" + id + "/stats");
  EXPECT_EQ(int(parse(stats)["frames"].size()), done);
}

TEST_F(ServerTest, EightConcurrentClientsAllGetTheirFrames) {
  service::ServerOptions o;
  o.queue = 64;
  start(o);
  // Eight clients at once, three frames each: nothing lost, every answer an image.
  std::atomic<int> ok{0}, bad{0};
  std::vector<std::thread> clients;
  for (int c = 0; c < 8; ++c) {
    clients.emplace_back([&, c] {
      for (int i = 0; i < 3; ++i) {
        auto r = post("/api/render",
                      {{"scene", "city"},
                       {"width", 96},
                       {"height", 64},
                       {"camera", {{"position", {10.0 * c, -50, 30}}, {"target", {60, 40, 0}}}}});
        (r && r->status == 200 && isJpeg(r->body) ? ok : bad)++;
      }
    });
  }
  for (auto& t : clients) t.join();
  EXPECT_EQ(ok.load(), 24);
  EXPECT_EQ(bad.load(), 0);
}

// The worker is held, so the first request stays in the queue for certain: the second finds
// the queue full, whatever the machine's speed.
TEST_F(ServerTest, PastTheQueueLimitRequestsGet503WithRetryAfter) {
  service::ServerOptions o;
  o.queue = 1;
  o.workers = 1;
  start(o);
  auto hold = server->holdWorkers();
  auto first = std::async(std::launch::async, [&] {
    return post("/api/render", {{"scene", "city"}, {"width", 64}, {"height", 48}})->status;
  });
  // Admitted: the queue holds it (the worker waits on the hold).
  bool queued = false;
  for (int i = 0; i < 2000 && !queued; ++i) {
    queued = client().Get("/metrics")->body.find("hlodr_queue_length 1\n") != std::string::npos;
    if (!queued) std::this_thread::yield();
  }
  ASSERT_TRUE(queued);
  auto busy = post("/api/render", {{"scene", "city"}, {"width", 32}, {"height", 32}});
  EXPECT_EQ(busy->status, 503);
  EXPECT_EQ(errorCode(busy), "busy");
  EXPECT_EQ(busy->get_header_value("Retry-After"), "1");
  hold.reset();
  EXPECT_EQ(first.get(), 200);
  EXPECT_EQ(post("/api/render", {{"scene", "city"}, {"width", 32}, {"height", 32}})->status, 200);
}

TEST_F(ServerTest, TwentyClientsDroppingTheirEventStreamsMidwayLeaveTheServerAnswering) {
  service::ServerOptions o;
  o.maxStreams = 25;
  start(o);
  const std::string id = newJob({{"frames", 600}, {"fps", 30}});
  ASSERT_FALSE(id.empty());
  std::vector<std::thread> clients;
  std::atomic<int> gotData{0};
  for (int c = 0; c < 20; ++c) {
    clients.emplace_back([&] {
      httplib::Client cl("127.0.0.1", port);
      int chunks = 0;
      // Returning false from the receiver drops the connection mid-stream.
      cl.Get(("/api/jobs/" + id + "/events").c_str(), [&](const char*, std::size_t) {
        if (++chunks == 1) ++gotData;
        return chunks < 3;
      });
    });
  }
  for (auto& t : clients) t.join();
  EXPECT_EQ(gotData.load(), 20);
  // Their slots come back within a second or two; the server answers meanwhile.
  auto h = client().Get("/healthz");
  ASSERT_TRUE(h);
  EXPECT_EQ(h->status, 200);
  bool freed = false;
  for (int i = 0; i < 50 && !freed; ++i) {
    const std::string m = client().Get("/metrics")->body;
    freed = m.find("hlodr_event_streams 0\n") != std::string::npos;
    if (!freed) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_TRUE(freed);
  EXPECT_EQ(client().Delete("/api/jobs/" + id)->status, 200);
}

// Two streams are open for certain (each has had its first event) when the third asks.
TEST_F(ServerTest, PastTheStreamLimitAnEventStreamGets503) {
  service::ServerOptions o;
  o.maxStreams = 2;
  start(o);
  const std::string id = newJob({{"frames", 900}, {"fps", 30}});
  std::atomic<bool> stop{false};
  std::vector<std::promise<void>> opened(2);
  std::vector<std::future<void>> open;
  for (auto& p : opened) open.push_back(p.get_future());
  std::vector<std::thread> holders;
  for (int c = 0; c < 2; ++c)
    holders.emplace_back([&, c] {
      httplib::Client cl("127.0.0.1", port);
      bool first = true;
      cl.Get(("/api/jobs/" + id + "/events").c_str(), [&](const char*, std::size_t) {
        if (first) opened[c].set_value();
        first = false;
        return !stop.load();
      });
      if (first) opened[c].set_value();  // no answer: the wait below must not hang
    });
  for (auto& f : open) f.wait();
  auto third = client().Get("/api/jobs/" + id + "/events");
  EXPECT_EQ(third->status, 503);
  EXPECT_FALSE(third->get_header_value("Retry-After").empty());
  stop = true;
  client().Delete("/api/jobs/" + id);
  for (auto& t : holders) t.join();
}

TEST_F(ServerTest, MetricsAreInThePrometheusFormatAndCountTheFrames) {
  start();
  ASSERT_EQ(post("/api/render", {{"scene", "city"}, {"width", 32}, {"height", 32}})->status, 200);
  auto m = client().Get("/metrics");
  ASSERT_TRUE(m);
  EXPECT_EQ(m->status, 200);
  EXPECT_EQ(m->get_header_value("Content-Type").rfind("text/plain; version=0.0.4", 0), 0u);
  const std::string text = m->body;
  for (const char* name :
       {"hlodr_frames_total{kind=\"render\"} 1", "# TYPE hlodr_frame_seconds histogram",
        "hlodr_frame_seconds_bucket{le=\"0.033\"}", "hlodr_frame_seconds_count 1",
        "hlodr_http_request_duration_seconds_count", "hlodr_queue_length", "hlodr_sessions",
        "hlodr_sessions_asking", "hlodr_jobs{state=\"running\"}", "hlodr_resident_bytes",
        "hlodr_loads_total"})
    EXPECT_NE(text.find(name), std::string::npos) << name << "\n" << text;
  // promtool (Debian's prometheus package) accepts it.
  if (std::system("command -v promtool >/dev/null 2>&1") != 0) {
    if (std::getenv("CI")) FAIL() << "promtool missing in CI (scripts/setup.sh installs it)";
    GTEST_SKIP() << "promtool not installed (apt-get install prometheus)";
  }
  const fs::path f = dataDir() / "metrics.txt";
  std::ofstream(f) << text;
  const std::string cmd = "promtool check metrics < " + f.string() + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  char buf[512];
  while (fgets(buf, sizeof buf, p)) out += buf;
  EXPECT_EQ(pclose(p), 0) << out;
}

TEST_F(ServerTest, StopCancelsRunningJobsAndTheyCloseTheirVideoAndStats) {
  start();
  const std::string id = newJob({{"frames", 3000}, {"fps", 30}, {"video", true}});
  for (int i = 0; i < 300; ++i) {
    if (parse(client().Get("/api/jobs/" + id))["framesDone"].get<int>() > 3) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  server->stop();
  thread.join();
  const fs::path dir = dataDir() / "jobs_StopCancelsRunningJobsAndTheyCloseTheirVideoAndStats" / id;
  ASSERT_TRUE(fs::exists(dir / "stats.json"));
  std::ifstream in(dir / "stats.json");
  const json stats = json::parse(in, nullptr, false);
  ASSERT_TRUE(stats.is_object());
  EXPECT_GT(stats["frames"].size(), 3u);
  // A closed MP4: ffprobe reads its duration (an unfinished one has no moov atom).
  if (std::system("command -v ffprobe >/dev/null 2>&1") == 0) {
    const std::string cmd = "ffprobe -v error -show_entries format=duration -of csv=p=0 " +
                            (dir / "video.mp4").string() + " >/dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
  }
}

TEST_F(ServerTest, ThePageIsServedAtTheRoot) {
  startWithPage();
  auto r = client().Get("/");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_NE(r->body.find("<title>hlodr</title>"), std::string::npos);
  EXPECT_EQ(client().Get("/../../etc/passwd")->status == 200 &&
                client().Get("/../../etc/passwd")->body.find("root:") != std::string::npos,
            false);
  EXPECT_EQ(client().Get("/api/scenes")->status, 200);  // the API still answers beside the files
}

TEST_F(ServerTest, AStudyRunsAsAJobAndServesItsReport) {
  start();
  auto r = post("/api/studies", {{"scene", "city"},
                                 {"path", {{"kind", "orbit"}}},
                                 {"frames", 2},
                                 {"budgets", {16, 33}},
                                 {"selectors", {"lakhia", "sse"}},
                                 {"ssePx", {8}},
                                 {"width", 160},
                                 {"height", 90},
                                 {"strips", 1}});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 202) << r->body;
  const std::string id = parse(r)["id"];
  EXPECT_EQ(parse(r)["kind"], "study");
  json study;
  for (int i = 0; i < 600; ++i) {
    study = parse(client().Get("/api/studies/" + id));
    if (study["finished"].get<bool>()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_EQ(study["state"], "done") << study.dump();
  EXPECT_DOUBLE_EQ(study["progress"].get<double>(), 1.0);
  const std::string report = study["outputs"]["report"];
  auto html = client().Get(report);
  ASSERT_TRUE(html);
  EXPECT_EQ(html->status, 200);
  EXPECT_NE(html->body.find("What accuracy costs in time"), std::string::npos);
  auto data = client().Get("/api/studies/" + id + "/report/study.json");
  ASSERT_EQ(data->status, 200);
  EXPECT_EQ(parse(data)["runs"].size(), 3u);  // lakhia 16, lakhia 33, sse 8 px
  EXPECT_EQ(client().Get("/api/studies/" + id + "/report/pareto.svg")->status, 200);
  for (const char* bad : {"..%2Fstudy.json", "STUDY.json", "study.json.bak", "a.exe", ".json"})
    EXPECT_EQ(client().Get("/api/studies/" + id + "/report/" + bad)->status, 404) << bad;
  // Not a path job: the job routes do not see it, the list of studies does.
  EXPECT_EQ(client().Get("/api/jobs/" + id)->status, 404);
  EXPECT_EQ(parse(client().Get("/api/studies"))["studies"][0]["id"], id);
  auto badStudy =
      post("/api/studies", {{"scene", "city"}, {"path", {{"kind", "orbit"}}}, {"budgets", {0}}});
  EXPECT_EQ(badStudy->status, 400);
  EXPECT_NE(errorMessage(badStudy).find("budgets"), std::string::npos);
  EXPECT_EQ(client().Delete("/api/studies/" + id)->status, 204);
}

TEST_F(ServerTest, AFailingRenderIsA500WithAMessageAndTheServerKeepsServing) {
  makeScene();
  // A copy of the store whose hlod_0 payloads are damaged: a session on it cannot start.
  const fs::path bad = dataDir() / "damaged.hlod";
  fs::remove_all(bad);
  fs::copy(dataDir() / "city.hlod", bad, fs::copy_options::recursive);
  {
    std::fstream f(bad / "payload.bin", std::ios::in | std::ios::out | std::ios::binary);
    const std::string junk(64, '\x5a');
    f.seekp(8);
    f.write(junk.data(), std::streamsize(junk.size()));
  }
  start();
  auto r = post("/api/sessions", {{"scene", "damaged"}});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 500) << r->body;
  EXPECT_EQ(errorCode(r), "internal");
  EXPECT_NE(errorMessage(r).find("hlod_0 node"), std::string::npos) << r->body;
  auto frame = post("/api/render", {{"scene", "damaged"}, {"width", 32}, {"height", 32}});
  EXPECT_EQ(frame->status, 500);
  auto ok = post("/api/render", {{"scene", "city"}, {"width", 32}, {"height", 32}});
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->status, 200);
  EXPECT_EQ(client().Get("/healthz")->status, 200);
  fs::remove_all(bad);
}

// A load balancer hashes the session id (docs/deploy.md): the client may propose it.
TEST_F(ServerTest, ASessionTakesTheIdItsClientProposesAndRefusesABadOrTakenOne) {
  start();
  auto made = post("/api/sessions",
                   {{"scene", "city"}, {"id", "page-0123abcd"}, {"width", 64}, {"height", 48}});
  ASSERT_EQ(made->status, 201) << made->body;
  EXPECT_EQ(parse(made)["id"], "page-0123abcd");
  EXPECT_EQ(post("/api/sessions/page-0123abcd/frame", json::object())->status, 200);
  auto again = post("/api/sessions", {{"scene", "city"}, {"id", "page-0123abcd"}});
  EXPECT_EQ(again->status, 409);
  EXPECT_EQ(errorCode(again), "conflict");
  for (const json& bad :
       {json("short"), json("has/slash-in-it"), json(12345678), json(std::string(65, 'a'))}) {
    auto r = post("/api/sessions", {{"scene", "city"}, {"id", bad}});
    EXPECT_EQ(r->status, 400) << bad;
    EXPECT_EQ(errorCode(r), "bad_request");
  }
}

TEST_F(ServerTest, DrainingAnswersHealthWith503AndStillServesSessions) {
  start();
  const std::string id = newSession();
  server->drain();
  auto h = client().Get("/healthz");
  ASSERT_TRUE(h);
  EXPECT_EQ(h->status, 503);
  EXPECT_EQ(parse(h)["status"], "draining");
  EXPECT_EQ(post("/api/sessions/" + id + "/frame", json::object())->status, 200);
}
