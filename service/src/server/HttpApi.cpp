// The HTTP API (docs/api.md): parse and validate on the HTTP thread, render on a worker, answer.
#include "server/HttpApi.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <utility>

#include "server/SceneChoice.h"

namespace service::server {

std::size_t ApiContext::queued() const {
  return inFlight.load();
}

namespace {

using httplib::Request;
using httplib::Response;

void sendJson(Response& res, int status, const nlohmann::json& body) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

void sendError(Response& res, const ApiError& e) {
  res.status = e.status;
  if (e.status == 503) res.set_header("Retry-After", "1");
  res.set_content(nlohmann::json{{"error", {{"code", e.code}, {"message", e.message}}}}.dump(),
                  "application/json");
}

bool jsonBody(const Request& req, Response& res) {
  if (req.body.empty()) return true;
  const std::string type = req.get_header_value("Content-Type");
  if (type.rfind("application/json", 0) != 0) {
    sendError(res, {415, "unsupported_media_type", "the body must be application/json"});
    return false;
  }
  return true;
}

void sendFrame(Response& res, const FrameAnswer& a, double totalMs) {
  const hlod::FrameRecord& r = a.record;
  char timing[400];
  std::snprintf(timing, sizeof timing,
                "queue;dur=%.2f, select;dur=%.2f, upload;dur=%.2f, draw;dur=%.2f, "
                "readback;dur=%.2f, encode;dur=%.2f, total;dur=%.2f",
                a.queueMs, r.selectorMs, r.uploadMs, r.drawMs, a.readbackMs, a.encodeMs, totalMs);
  res.set_header("Server-Timing", timing);
  nlohmann::json stats = nlohmann::json::parse(hlod::frameJson(r));
  if (!a.session.empty()) stats["session"] = a.session;
  res.set_header("X-Hlodr-Stats", stats.dump());
  res.set_header("Cache-Control", "no-store");
  res.status = 200;
  res.set_content(reinterpret_cast<const char*>(a.bytes.data()), a.bytes.size(),
                  renderer::mimeType(a.format));
}

bool sendFile(Response& res, const std::filesystem::path& path, const char* type) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  res.status = 200;
  res.set_content(std::move(bytes), type);
  return true;
}

// A place in the render queue, held from admission until the answer is ready (the worker's own
// task counter would still count a task whose answer has gone out).
class QueueSlot {
 public:
  explicit QueueSlot(std::atomic<std::size_t>* n) : n_(n) {}
  QueueSlot(QueueSlot&& o) noexcept : n_(std::exchange(o.n_, nullptr)) {}
  QueueSlot(const QueueSlot&) = delete;
  ~QueueSlot() {
    if (n_) --*n_;
  }
  explicit operator bool() const { return n_ != nullptr; }

 private:
  std::atomic<std::size_t>* n_;
};

// Room in the render queue: past it, 503 with Retry-After (the client tries again).
QueueSlot admit(ApiContext& api, Response& res) {
  if (api.stopping) {
    sendError(res, {503, "busy", "the server is shutting down"});
    return QueueSlot(nullptr);
  }
  if (++api.inFlight > api.queueLimit) {
    --api.inFlight;
    api.metrics.add("hlodr_rejected_total", "reason=\"queue\"");
    sendError(res, {503, "busy",
                    "the render queue is full (" + std::to_string(api.queueLimit) +
                        " requests); try again"});
    return QueueSlot(nullptr);
  }
  return QueueSlot(&api.inFlight);
}

std::shared_ptr<Job> jobOfKind(ApiContext& api, const std::string& id, const std::string& kind) {
  auto job = api.jobs.find(id);
  return job && job->kind == kind ? job : nullptr;
}

std::shared_ptr<Job> pathJob(ApiContext& api, const std::string& id) {
  return jobOfKind(api, id, "path");
}

std::shared_ptr<Job> studyJob(ApiContext& api, const std::string& id) {
  return jobOfKind(api, id, "study");
}

// GET /api/COLLECTION, GET and DELETE /api/COLLECTION/{id} for the jobs of one kind: a DELETE
// cancels a queued or running one (200, its object) or removes a finished one (204).
void jobRoutes(httplib::Server& http, ApiContext& api, const std::string& collection,
               const std::string& kind, const std::string& noun) {
  http.Get("/api/" + collection, [&api, collection, kind](const Request&, Response& res) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& j : api.jobs.list())
      if (j->kind == kind) list.push_back(j->json());
    sendJson(res, 200, {{collection, list}});
  });
  const std::string one = "/api/" + collection + "/([^/]+)";
  http.Get(one, [&api, kind, noun](const Request& req, Response& res) {
    auto job = jobOfKind(api, req.matches[1], kind);
    if (!job) return sendError(res, notFound("no " + noun + " " + std::string(req.matches[1])));
    sendJson(res, 200, job->json());
  });
  http.Delete(one, [&api, kind, noun](const Request& req, Response& res) {
    if (!jobOfKind(api, req.matches[1], kind))
      return sendError(res, notFound("no " + noun + " " + std::string(req.matches[1])));
    auto r = api.jobs.cancelOrRemove(req.matches[1]);
    if (!r) return sendError(res, r.error());
    if (*r) {
      auto job = api.jobs.find(req.matches[1]);
      sendJson(res, 200, job ? job->json() : nlohmann::json::object());
    } else {
      res.status = 204;
    }
  });
}

// One slot of --max-streams, given back when the stream ends or its client goes away.
struct StreamSlot {
  explicit StreamSlot(std::atomic<std::size_t>& n) : count(n) {}
  ~StreamSlot() { --count; }
  std::atomic<std::size_t>& count;
};

}  // namespace

void installRoutes(httplib::Server& http, ApiContext& api) {
  http.Get("/healthz", [&](const Request&, Response& res) {
    sendJson(res, 200,
             {{"status", api.stopping ? "stopping" : "ok"},
              {"workers", api.workers.size()},
              {"scenes", api.scenes.all().size()}});
  });

  http.Get("/metrics", [&](const Request&, Response& res) {
    res.set_content(api.metrics.text(), "text/plain; version=0.0.4; charset=utf-8");
  });

  http.Get("/api/scenes", [&](const Request&, Response& res) {
    api.scenes.scan(api.log);  // stores built since the start appear
    // The data folder's scene files, read once, each under its store (the page's scene picker).
    const auto files = api.scenes.sceneFiles();
    nlohmann::json list = nlohmann::json::array();
    for (const auto& s : api.scenes.all()) {
      nlohmann::json j = s->summary();
      j["sceneFiles"] = nlohmann::json::array();
      for (const auto& f : files)
        if (f.storeId == s->id)
          j["sceneFiles"].push_back(
              {{"name", f.name}, {"effects", hlod::declaredEffects(f.file.effects)}});
      list.push_back(std::move(j));
    }
    sendJson(res, 200, {{"scenes", list}});
  });

  http.Get(R"(/api/scenes/([^/]+))", [&](const Request& req, Response& res) {
    auto scene = api.scenes.find(req.matches[1]);
    if (!scene) return sendError(res, notFound("no scene '" + std::string(req.matches[1]) + "'"));
    sendJson(res, 200, scene->detail());
  });

  http.Post("/api/render", [&](const Request& req, Response& res) {
    const auto start = Clock::now();
    if (!jsonBody(req, res)) return;
    std::set<std::string> fields = renderSettingFields();
    fields.insert({"scene", "camera", "mode", "format", "quality"});
    fields.erase("memoryMb");
    auto in = JsonInput::parse(req.body, fields);
    if (!in) return sendError(res, badRequest(in.message()));
    auto choice = readSceneChoice(in->json().value("scene", nlohmann::json()), api.scenes);
    if (!choice) return sendError(res, choice.error());
    auto scene = choice->store;
    auto settings = readRenderSettings(*in, api.maxSize, false);
    if (!settings) return sendError(res, settings.error());
    choice->applyTo(*settings);
    auto image = readImageRequest(*in);
    if (!image) return sendError(res, image.error());
    auto mode = in->choice("mode", "settled", {"settled", "realtime"});
    if (!mode) return sendError(res, badRequest(mode.message()));
    hlod::Camera camera =
        scene->defaultCamera(double(settings->width) / settings->height, settings->camera);
    if (in->has("camera")) {
      auto c = cameraFrom(in->json()["camera"], camera);
      if (!c) return sendError(res, badRequest(c.message()));
      camera = *c;
    }
    auto slot = admit(api, res);
    if (!slot) return;
    auto a = api.sessions.renderOnce(
        scene, *settings, camera,
        *mode == "realtime" ? hlod::FrameMode::Realtime : hlod::FrameMode::Settled, *image);
    if (!a) return sendError(res, a.error());
    sendFrame(res, *a, msSince(start));
  });

  http.Post("/api/sessions", [&](const Request& req, Response& res) {
    if (!jsonBody(req, res)) return;
    std::set<std::string> fields = renderSettingFields();
    fields.insert("scene");
    auto in = JsonInput::parse(req.body, fields);
    if (!in) return sendError(res, badRequest(in.message()));
    auto choice = readSceneChoice(in->json().value("scene", nlohmann::json()), api.scenes);
    if (!choice) return sendError(res, choice.error());
    auto scene = choice->store;
    auto settings = readRenderSettings(*in, api.maxSize, true);
    if (!settings) return sendError(res, settings.error());
    choice->applyTo(*settings);
    auto slot = admit(api, res);
    if (!slot) return;
    auto made = api.sessions.create(scene, *settings);
    if (!made) return sendError(res, made.error());
    sendJson(res, 201, *made);
  });

  http.Post(R"(/api/sessions/([^/]+)/frame)", [&](const Request& req, Response& res) {
    const auto start = Clock::now();
    if (!jsonBody(req, res)) return;
    auto in = JsonInput::parse(req.body, {"camera", "still", "format", "quality"});
    if (!in) return sendError(res, badRequest(in.message()));
    auto still = in->boolean("still", false);
    if (!still) return sendError(res, badRequest(still.message()));
    auto image = readImageRequest(*in);
    if (!image) return sendError(res, image.error());
    auto slot = admit(api, res);
    if (!slot) return;
    const nlohmann::json camera = in->has("camera") ? in->json()["camera"] : nlohmann::json();
    auto a = api.sessions.frame(req.matches[1], camera, *still, *image);
    if (!a) return sendError(res, a.error());
    sendFrame(res, *a, msSince(start));
  });

  http.Get(R"(/api/sessions/([^/]+))", [&](const Request& req, Response& res) {
    auto j = api.sessions.info(req.matches[1]);
    if (!j) return sendError(res, j.error());
    sendJson(res, 200, *j);
  });

  http.Delete(R"(/api/sessions/([^/]+))", [&](const Request& req, Response& res) {
    if (!api.sessions.remove(req.matches[1]))
      return sendError(res, notFound("no session " + std::string(req.matches[1])));
    res.status = 204;
  });

  http.Post("/api/jobs", [&](const Request& req, Response& res) {
    if (!jsonBody(req, res)) return;
    std::set<std::string> fields = renderSettingFields();
    fields.insert({"scene", "path", "fps", "mode", "video", "frames", "prefetch"});
    auto in = JsonInput::parse(req.body, fields);
    if (!in) return sendError(res, badRequest(in.message()));
    auto choice = readSceneChoice(in->json().value("scene", nlohmann::json()), api.scenes);
    if (!choice) return sendError(res, choice.error());
    auto scene = choice->store;
    auto render = readRenderSettings(*in, api.maxSize, true);
    if (!render) return sendError(res, render.error());
    choice->applyTo(*render);
    JobSettings s;
    s.render = *render;
    auto fps = in->number("fps", 30.0, 1.0, 240.0);
    auto mode = in->choice("mode", "realtime", {"realtime", "settled"});
    auto video = in->boolean("video", false);
    auto frames = in->integer("frames", -1, 1, 100000000);
    auto prefetch = in->boolean("prefetch", false);
    if (!fps) return sendError(res, badRequest(fps.message()));
    if (!mode) return sendError(res, badRequest(mode.message()));
    if (!video) return sendError(res, badRequest(video.message()));
    if (!frames) return sendError(res, badRequest(frames.message()));
    if (!prefetch) return sendError(res, badRequest(prefetch.message()));
    s.fps = *fps;
    s.mode = *mode == "settled" ? hlod::FrameMode::Settled : hlod::FrameMode::Realtime;
    s.video = *video;
    s.frames = *frames;
    s.prefetch = *prefetch;
    auto spec = readPathSpec(*in);
    if (!spec) return sendError(res, spec.error());
    s.path = *spec;
    if (api.stopping) return sendError(res, {503, "busy", "the server is shutting down"});
    auto job = api.jobs.submit(scene, std::move(s));
    if (!job) return sendError(res, job.error());
    sendJson(res, 202, *job);
  });

  jobRoutes(http, api, "jobs", "path", "job");

  http.Get(R"(/api/jobs/([^/]+)/frames/(\d{1,9}))", [&](const Request& req, Response& res) {
    auto job = pathJob(api, req.matches[1]);
    if (!job) return sendError(res, notFound("no job " + std::string(req.matches[1])));
    const std::uint64_t n = std::stoull(req.matches[2]);
    const auto path = job->framePath(n);
    if (path.empty() || !sendFile(res, path, "image/jpeg"))
      return sendError(res, notFound("frame " + std::to_string(n) + " is not rendered"));
  });

  auto stats = [&](const Request& req, Response& res, bool csv) {
    auto job = pathJob(api, req.matches[1]);
    if (!job) return sendError(res, notFound("no job " + std::string(req.matches[1])));
    if (csv || req.get_param_value("format") == "csv") {
      res.set_header("Content-Disposition", "attachment; filename=\"" + job->id + ".stats.csv\"");
      res.set_content(job->statsCsv(), "text/csv");
    } else {
      res.set_content(job->statsJson(), "application/json");
    }
  };
  http.Get(R"(/api/jobs/([^/]+)/stats)",
           [stats](const Request& req, Response& res) { stats(req, res, false); });
  http.Get(R"(/api/jobs/([^/]+)/stats\.csv)",
           [stats](const Request& req, Response& res) { stats(req, res, true); });

  http.Get(R"(/api/jobs/([^/]+)/video\.mp4)", [&](const Request& req, Response& res) {
    auto job = pathJob(api, req.matches[1]);
    if (!job) return sendError(res, notFound("no job " + std::string(req.matches[1])));
    if (!job->settings.video) return sendError(res, notFound("job " + job->id + " has no video"));
    if (job->state() != JobState::Done)
      return sendError(res, {409, "conflict",
                             "job " + job->id + " is " + jobStateName(job->state()) +
                                 ": its video exists once it is done"});
    if (!sendFile(res, job->videoPath(), "video/mp4"))
      return sendError(res, {500, "internal", "the video of job " + job->id + " is missing"});
    res.set_header("Content-Disposition", "attachment; filename=\"" + job->id + ".mp4\"");
  });

  http.Get(R"(/api/jobs/([^/]+)/events)", [&](const Request& req, Response& res) {
    auto job = pathJob(api, req.matches[1]);
    if (!job) return sendError(res, notFound("no job " + std::string(req.matches[1])));
    if (++api.streams > api.maxStreams) {
      --api.streams;
      api.metrics.add("hlodr_rejected_total", "reason=\"streams\"");
      return sendError(
          res, {503, "busy",
                "at most " + std::to_string(api.maxStreams) + " event streams at once; try again"});
    }
    auto slot = std::make_shared<StreamSlot>(api.streams);
    struct Cursor {
      std::size_t sent = 0;
      JobState known = JobState::Queued;
      bool first = true, ended = false;
    };
    auto cur = std::make_shared<Cursor>();
    res.set_header("Cache-Control", "no-cache");
    res.set_chunked_content_provider(
        "text/event-stream",
        [job, cur, slot](std::size_t, httplib::DataSink& sink) {
          if (cur->ended) {
            sink.done();
            return true;
          }
          if (!sink.is_writable()) return false;  // the client went away: free the thread
          // Waits at most a second, so that a client gone quiet is noticed soon.
          auto ev = job->eventsFrom(cur->sent, cur->known, std::chrono::milliseconds(1000));
          std::string out;
          for (const auto& f : ev.frames) out += "event: frame\ndata: " + f + "\n\n";
          cur->sent += ev.frames.size();
          const nlohmann::json state = {{"state", jobStateName(ev.state)},
                                        {"framesDone", ev.framesDone},
                                        {"framesTotal", job->framesTotal}};
          if (ev.changedState || cur->first) out += "event: state\ndata: " + state.dump() + "\n\n";
          cur->first = false;
          cur->known = ev.state;
          const bool over = ev.state == JobState::Done || ev.state == JobState::Failed ||
                            ev.state == JobState::Cancelled;
          if (over && cur->sent >= ev.framesDone) {
            nlohmann::json end = job->json();
            out += "event: end\ndata: " +
                   nlohmann::json{{"state", end["state"]}, {"summary", end["summary"]}}.dump() +
                   "\n\n";
            cur->ended = true;
          }
          if (out.empty()) out = ": keep-alive\n\n";  // a write to a gone client fails here
          if (!sink.write(out.data(), out.size())) return false;
          if (cur->ended) sink.done();
          return true;
        },
        [slot](bool) {});
  });

  http.Post("/api/studies", [&](const Request& req, Response& res) {
    if (!jsonBody(req, res)) return;
    auto in = JsonInput::parse(req.body, {"scene", "path", "budgets", "selectors", "ssePx", "width",
                                          "height", "frames", "fps", "mode", "strips"});
    if (!in) return sendError(res, badRequest(in.message()));
    auto id = in->string("scene", 64);
    if (!id) return sendError(res, badRequest(id.message()));
    auto scene = api.scenes.find(*id);
    if (!scene) return sendError(res, notFound("no scene '" + *id + "'"));
    StudyOptions o;
    auto budgets = numbers(*in, "budgets", o.budgets, 1.0, 10000.0);
    auto sse = numbers(*in, "ssePx", o.ssePx, 0.1, 1000.0);
    auto w = in->integer("width", 640, 16, api.maxSize);
    auto h = in->integer("height", 360, 16, api.maxSize);
    auto frames = in->integer("frames", 24, 1, 1000);
    auto fps = in->number("fps", 30.0, 1.0, 240.0);
    auto strips = in->integer("strips", 3, 0, 10);
    auto mode = in->choice("mode", "settled", {"settled", "realtime", "both"});
    for (const auto* r : {&budgets, &sse})
      if (!*r) return sendError(res, r->error());
    for (const auto* r : {&w, &h, &frames, &strips})
      if (!*r) return sendError(res, badRequest(r->message()));
    if (!fps) return sendError(res, badRequest(fps.message()));
    if (!mode) return sendError(res, badRequest(mode.message()));
    if (in->has("selectors")) {
      const auto& v = in->json()["selectors"];
      o.selectors.clear();
      if (!v.is_array() || v.empty() || v.size() > 3)
        return sendError(res, badRequest("selectors: must be a list of lakhia, sse, fs"));
      for (const auto& x : v) {
        if (!x.is_string() || (x != "lakhia" && x != "sse" && x != "fs"))
          return sendError(res, badRequest("selectors: must be a list of lakhia, sse, fs"));
        o.selectors.push_back(x.get<std::string>());
      }
    }
    o.budgets = *budgets;
    o.ssePx = *sse;
    o.width = int(*w);
    o.height = int(*h);
    o.frames = std::size_t(*frames);
    o.fps = *fps;
    o.stripFrames = std::size_t(*strips);
    o.settled = *mode != "realtime";
    o.realtime = *mode != "settled";
    auto spec = readPathSpec(*in);
    if (!spec) return sendError(res, spec.error());
    JobSettings s;
    s.path = *spec;
    s.fps = o.fps;
    if (api.stopping) return sendError(res, {503, "busy", "the server is shutting down"});
    auto job = api.jobs.submitStudy(scene, std::move(s), std::move(o));
    if (!job) return sendError(res, job.error());
    sendJson(res, 202, *job);
  });

  jobRoutes(http, api, "studies", "study", "study");

  http.Get(R"(/api/studies/([^/]+)/report/([^/]+))", [&](const Request& req, Response& res) {
    auto job = studyJob(api, req.matches[1]);
    if (!job) return sendError(res, notFound("no study " + std::string(req.matches[1])));
    const std::string name = req.matches[2];
    const auto file = job->reportFile(name);
    if (file.empty())
      return sendError(res, notFound("the report has no file " + name.substr(0, 64)));
    const std::string ext = name.substr(name.rfind('.') + 1);
    const char* type = ext == "html"  ? "text/html; charset=utf-8"
                       : ext == "svg" ? "image/svg+xml"
                       : ext == "png" ? "image/png"
                       : ext == "csv" ? "text/csv"
                                      : "application/json";
    if (!sendFile(res, file, type)) return sendError(res, notFound("no file " + name));
  });
}

}  // namespace service::server
