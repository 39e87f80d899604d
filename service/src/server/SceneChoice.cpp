#include "server/SceneChoice.h"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace service::server {

ApiResult<SceneChoice> readSceneChoice(const nlohmann::json& value, const SceneRegistry& scenes) {
  SceneChoice choice;
  hlod::SceneFile file;
  if (value.is_string() && value.get<std::string>().ends_with(".json")) {
    const std::string name = value.get<std::string>();
    // A name in the data folder, checked as store ids are: no path reaches outside it.
    if (!SceneRegistry::validId(name)) return badRequest("scene: not a valid scene file name");
    const auto path = scenes.dataDir() / name;
    std::ifstream in(path, std::ios::binary);
    if (!in) return notFound("no scene file '" + name + "'");
    std::ostringstream text;
    text << in.rdbuf();
    auto parsed = hlod::parseScene(text.str());
    if (!parsed) return badRequest(name + ": " + parsed.message());
    file = std::move(*parsed);
    if (file.store.empty()) return badRequest(name + ": store: is required");
    choice.key = "file:" + name + ":" + std::to_string(std::hash<std::string>{}(text.str()));
    choice.file = name;
  } else if (value.is_object()) {
    auto parsed = hlod::parseScene(value.dump());
    if (!parsed) return badRequest("scene." + parsed.message());
    file = std::move(*parsed);
    if (file.store.empty()) return badRequest("scene.store: is required");
    choice.key = value.dump();
  } else if (value.is_string() && !value.get<std::string>().empty()) {
    file.store = value.get<std::string>();
    file.effects = hlod::defaultEffects();
  } else {
    return badRequest("scene: must be a store id, a scene file name (NAME.json) or a scene object");
  }
  const std::string id = SceneRegistry::storeIdOf(file.store);
  choice.store = scenes.find(id);
  if (!choice.store) return notFound("no scene '" + id + "'");
  choice.effects = file.effects;
  choice.camera = file.camera;
  return choice;
}

}  // namespace service::server
