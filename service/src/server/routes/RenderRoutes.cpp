// POST /api/render: one frame on request, on a warm session of the least busy worker.
#include "server/ApiReply.h"
#include "server/SceneChoice.h"
#include "server/routes/Routes.h"

namespace service::server {

void installRenderRoutes(httplib::Server& http, ApiContext& api) {
  http.Post("/api/render", [&](const httplib::Request& req, httplib::Response& res) {
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
    auto mode = in->choice(settings::get("frameMode"));
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
}

}  // namespace service::server
