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
    using settings::get;
    StudyOptions o;
    auto budgets = in->numbers(get("study.budgets"));
    auto sse = in->numbers(get("study.ssePx"));
    auto selectors = in->choices(get("study.selectors"));
    auto w = in->integer(get("width"), api.maxSize);
    auto h = in->integer(get("height"), api.maxSize);
    auto frames = in->integer(get("study.frames"));
    auto fps = in->number(get("fps"));
    auto strips = in->integer(get("study.strips"));
    auto mode = in->choice(get("study.mode"));
    if (!budgets) return sendError(res, badRequest(budgets.message()));
    if (!sse) return sendError(res, badRequest(sse.message()));
    if (!selectors) return sendError(res, badRequest(selectors.message()));
    for (const auto* r : {&w, &h, &frames, &strips})
      if (!*r) return sendError(res, badRequest(r->message()));
    if (!fps) return sendError(res, badRequest(fps.message()));
    if (!mode) return sendError(res, badRequest(mode.message()));
    o.selectors = *selectors;
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

  installJobCollectionRoutes(http, api, "studies", {"study"}, "study");

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
