// /api/studies: accuracy studies as jobs (hlodr study), and their reports' files.
#include "server/ApiReply.h"
#include "server/routes/Routes.h"

namespace service::server {

using httplib::Request;
using httplib::Response;

void installStudyRoutes(httplib::Server& http, ApiContext& api) {
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

  installJobCollectionRoutes(http, api, "studies", "study", "study");

  http.Get(R"(/api/studies/([^/]+)/report/([^/]+))", [&](const Request& req, Response& res) {
    auto id = pathParam(req, 1, "study id", res);
    if (!id) return;
    auto name = pathParam(req, 2, "file", res);
    if (!name) return;
    auto job = api.jobs.find(*id);
    if (!job || job->kind != "study") return sendError(res, notFound("no study " + *id));
    const auto file = job->reportFile(*name);
    if (file.empty())
      return sendError(res, notFound("the report has no file " + name->substr(0, 64)));
    const std::string ext = name->substr(name->rfind('.') + 1);
    const char* type = ext == "html"  ? "text/html; charset=utf-8"
                       : ext == "svg" ? "image/svg+xml"
                       : ext == "png" ? "image/png"
                       : ext == "csv" ? "text/csv"
                                      : "application/json";
    if (!sendFile(res, file, type)) return sendError(res, notFound("no file " + *name));
  });
}

}  // namespace service::server
