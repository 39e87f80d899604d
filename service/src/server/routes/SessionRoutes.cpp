// /api/sessions: interactive viewing sessions (create, frame, info, delete).
#include <algorithm>
#include <cctype>

#include "server/ApiReply.h"
#include "server/SceneChoice.h"
#include "server/routes/Routes.h"

namespace service::server {

void installSessionRoutes(httplib::Server& http, ApiContext& api) {
  using httplib::Request;
  using httplib::Response;
  http.Post("/api/sessions", [&](const Request& req, Response& res) {
    if (!jsonBody(req, res)) return;
    std::set<std::string> fields = renderSettingFields();
    fields.insert("scene");
    fields.insert("id");
    auto in = JsonInput::parse(req.body, fields);
    if (!in) return sendError(res, badRequest(in.message()));
    // A client may propose the id, so that a load balancer can hash it before the session
    // exists (docs/deploy.md); a narrow alphabet keeps it safe in paths and logs.
    std::string id;
    if (in->has("id")) {
      const auto& v = in->json()["id"];
      if (v.is_string()) id = v.get<std::string>();
      const bool ok =
          id.size() >= 8 && id.size() <= 64 && std::all_of(id.begin(), id.end(), [](char c) {
            return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
          });
      if (!ok)
        return sendError(res, badRequest("id: must be 8..64 characters of A-Z, a-z, 0-9, - and _"));
    }
    auto choice = readSceneChoice(in->json().value("scene", nlohmann::json()), api.scenes);
    if (!choice) return sendError(res, choice.error());
    auto scene = choice->store;
    auto settings = readRenderSettings(*in, api.maxSize, true);
    if (!settings) return sendError(res, settings.error());
    choice->applyTo(*settings);
    auto slot = admit(api, res);
    if (!slot) return;
    auto made = api.sessions.create(scene, *settings, id);
    if (!made) return sendError(res, made.error());
    sendJson(res, 201, *made);
  });

  http.Post(R"(/api/sessions/([^/]+)/frame)", [&](const Request& req, Response& res) {
    const auto start = Clock::now();
    auto id = pathParam(req, 1, "session id", res);
    if (!id) return;
    if (!jsonBody(req, res)) return;
    auto in = JsonInput::parse(req.body, {"camera", "still", "format", "quality"});
    if (!in) return sendError(res, badRequest(in.message()));
    auto still = in->boolean(settings::get("still"));
    if (!still) return sendError(res, badRequest(still.message()));
    auto image = readImageRequest(*in);
    if (!image) return sendError(res, image.error());
    auto slot = admit(api, res);
    if (!slot) return;
    const nlohmann::json camera = in->has("camera") ? in->json()["camera"] : nlohmann::json();
    auto a = api.sessions.frame(*id, camera, *still, *image);
    if (!a) return sendError(res, a.error());
    sendFrame(res, *a, msSince(start));
  });

  http.Get(R"(/api/sessions/([^/]+))", [&](const Request& req, Response& res) {
    auto id = pathParam(req, 1, "session id", res);
    if (!id) return;
    auto j = api.sessions.info(*id);
    if (!j) return sendError(res, j.error());
    sendJson(res, 200, *j);
  });

  http.Delete(R"(/api/sessions/([^/]+))", [&](const Request& req, Response& res) {
    auto id = pathParam(req, 1, "session id", res);
    if (!id) return;
    if (!api.sessions.remove(*id)) return sendError(res, notFound("no session " + *id));
    res.status = 204;
  });
}

}  // namespace service::server
