// GET /api/scenes and GET /api/scenes/{id}: the node stores of the data folder.
#include "server/ApiReply.h"
#include "server/routes/Routes.h"

namespace service::server {

void installSceneRoutes(httplib::Server& http, ApiContext& api) {
  http.Get("/api/scenes", [&](const httplib::Request&, httplib::Response& res) {
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

  http.Get(R"(/api/scenes/([^/]+))", [&](const httplib::Request& req, httplib::Response& res) {
    auto id = pathParam(req, 1, "scene id", res);
    if (!id) return;
    auto scene = api.scenes.find(*id);
    if (!scene) return sendError(res, notFound("no scene '" + *id + "'"));
    sendJson(res, 200, scene->detail());
  });
}

}  // namespace service::server
