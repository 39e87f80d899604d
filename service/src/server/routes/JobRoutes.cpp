// /api/jobs: path jobs (submit, list, cancel or remove, frames, stats, video, event stream), and
// the collection routes that studies share. 3D Tiles exports are listed, read and removed here
// too (routes/ExportRoutes.cpp has the rest of them).
#include <algorithm>

#include "server/ApiReply.h"
#include "server/SceneChoice.h"
#include "server/routes/Routes.h"

namespace service::server {

using httplib::Request;
using httplib::Response;

namespace {

std::shared_ptr<Job> jobOfKind(ApiContext& api, const std::string& id,
                               const std::vector<std::string>& kinds) {
  auto job = api.jobs.find(id);
  return job && std::find(kinds.begin(), kinds.end(), job->kind) != kinds.end() ? job : nullptr;
}

// The path job named by the route's first parameter; answered 400 or 404 when there is none.
std::shared_ptr<Job> pathJobOf(ApiContext& api, const Request& req, Response& res) {
  auto id = pathParam(req, 1, "job id", res);
  if (!id) return nullptr;
  auto job = jobOfKind(api, *id, {"path"});
  if (!job) sendError(res, notFound("no path job " + *id));
  return job;
}

// One slot of --max-streams, given back when the stream ends or its client goes away.
struct StreamSlot {
  explicit StreamSlot(std::atomic<std::size_t>& n) : count(n) {}
  ~StreamSlot() { --count; }
  std::atomic<std::size_t>& count;
};

void eventStream(ApiContext& api, const std::shared_ptr<Job>& job, Response& res) {
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
}

}  // namespace

void installJobCollectionRoutes(httplib::Server& http, ApiContext& api,
                                const std::string& collection,
                                const std::vector<std::string>& kinds, const std::string& noun) {
  const std::string idName = noun + " id";
  http.Get("/api/" + collection, [&api, collection, kinds](const Request&, Response& res) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& j : api.jobs.list())
      if (std::find(kinds.begin(), kinds.end(), j->kind) != kinds.end()) list.push_back(j->json());
    sendJson(res, 200, {{collection, list}});
  });
  const std::string one = "/api/" + collection + "/([^/]+)";
  http.Get(one, [&api, kinds, noun, idName](const Request& req, Response& res) {
    auto id = pathParam(req, 1, idName.c_str(), res);
    if (!id) return;
    auto job = jobOfKind(api, *id, kinds);
    if (!job) return sendError(res, notFound("no " + noun + " " + *id));
    sendJson(res, 200, job->json());
  });
  http.Delete(one, [&api, kinds, noun, idName](const Request& req, Response& res) {
    auto id = pathParam(req, 1, idName.c_str(), res);
    if (!id) return;
    if (!jobOfKind(api, *id, kinds)) return sendError(res, notFound("no " + noun + " " + *id));
    auto r = api.jobs.cancelOrRemove(*id);
    if (!r) return sendError(res, r.error());
    if (*r) {
      auto job = api.jobs.find(*id);
      sendJson(res, 200, job ? job->json() : nlohmann::json::object());
    } else {
      res.status = 204;
    }
  });
}

void installJobRoutes(httplib::Server& http, ApiContext& api) {
  http.Post("/api/jobs", [&](const Request& req, Response& res) {
    if (!jsonBody(req, res)) return;
    std::set<std::string> fields = renderSettingFields();
    fields.insert({"scene", "path", "fps", "mode", "video", "frames", "prefetch", "segments"});
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
    using settings::get;
    auto fps = in->number(get("fps"));
    auto mode = in->choice(get("mode"));
    auto video = in->boolean(get("video"));
    auto frames = in->integer(get("frames"));
    auto prefetch = in->boolean(get("prefetch"));
    auto segments = in->integer(get("segments"));
    if (!segments) return sendError(res, badRequest(segments.message()));
    if (!fps) return sendError(res, badRequest(fps.message()));
    if (!mode) return sendError(res, badRequest(mode.message()));
    if (!video) return sendError(res, badRequest(video.message()));
    if (!frames) return sendError(res, badRequest(frames.message()));
    if (!prefetch) return sendError(res, badRequest(prefetch.message()));
    s.fps = *fps;
    s.mode = *mode == "settled" ? hlod::FrameMode::Settled : hlod::FrameMode::Realtime;
    s.video = *video;
    s.frames = in->has("frames") ? *frames : -1;
    s.prefetch = *prefetch;
    s.segments = static_cast<std::uint32_t>(*segments);
    auto spec = readPathSpec(*in);
    if (!spec) return sendError(res, spec.error());
    s.path = *spec;
    if (api.stopping) return sendError(res, {503, "busy", "the server is shutting down"});
    auto job = api.jobs.submit(scene, std::move(s));
    if (!job) return sendError(res, job.error());
    sendJson(res, 202, *job);
  });

  installJobCollectionRoutes(http, api, "jobs", {"path", "export"}, "job");

  http.Get(R"(/api/jobs/([^/]+)/frames/(\d{1,9}))", [&](const Request& req, Response& res) {
    auto job = pathJobOf(api, req, res);
    if (!job) return;
    const std::uint64_t n = std::stoull(req.matches[2]);
    const auto path = job->framePath(n);
    if (path.empty() || !sendFile(res, path, "image/jpeg"))
      return sendError(res, notFound("frame " + std::to_string(n) + " is not rendered"));
  });

  auto stats = [&](const Request& req, Response& res, bool csv) {
    auto job = pathJobOf(api, req, res);
    if (!job) return;
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

  http.Get(R"(/api/jobs/([^/]+)/trace\.json)", [&](const Request& req, Response& res) {
    auto job = pathJobOf(api, req, res);
    if (!job) return;
    auto trace = job->traceJson();
    if (!trace) return sendError(res, notFound("job " + job->id + " has no frames yet"));
    res.set_header("Content-Disposition", "attachment; filename=\"" + job->id + ".trace.json\"");
    res.set_content(std::move(*trace), "application/json");
  });

  http.Get(R"(/api/jobs/([^/]+)/video\.mp4)", [&](const Request& req, Response& res) {
    auto job = pathJobOf(api, req, res);
    if (!job) return;
    if (!job->settings.video) return sendError(res, notFound("job " + job->id + " has no video"));
    // A cancelled job closes its video like a finished one: what it rendered is a valid MP4.
    if (!job->videoReady())
      return sendError(res, {409, "conflict",
                             "job " + job->id + " is " + jobStateName(job->state()) +
                                 ": its video exists once it is done or cancelled after its "
                                 "first frame"});
    if (!sendFile(res, job->videoPath(), "video/mp4"))
      return sendError(res, {500, "internal", "the video of job " + job->id + " is missing"});
    res.set_header("Content-Disposition", "attachment; filename=\"" + job->id + ".mp4\"");
  });

  http.Get(R"(/api/jobs/([^/]+)/events)", [&](const Request& req, Response& res) {
    auto job = pathJobOf(api, req, res);
    if (job) eventStream(api, job, res);
  });
}

}  // namespace service::server
