#pragma once
// The `scene` field of a render, session or job request: a store id ("city": the default
// effects), a scene file in the data folder ("city.json"), or a scene inline (an object of the
// scene file's schema, docs/scene.md, whose "store" is the store id). Scene files are read from
// the data folder by name only, never by a client's path.
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "hlod/scene/SceneFile.h"
#include "server/ApiTypes.h"
#include "server/SceneRegistry.h"

namespace service::server {

struct SceneChoice {
  std::shared_ptr<Scene> store;
  hlod::SceneEffects effects = hlod::defaultEffects();
  std::optional<hlod::SceneCamera> camera;  // the scene file's default camera
  std::string key;   // equal for equal effects: part of a warm session's key ("" for defaults)
  std::string file;  // the scene file's name, when the scene is one
  // Its effects, key and camera into the settings of a render, session or job.
  void applyTo(RenderSettings& settings) const {
    settings.effects = effects;
    settings.effectsKey = key;
    settings.camera = camera;
    settings.sceneFile = file;
  }
};

ApiResult<SceneChoice> readSceneChoice(const nlohmann::json& value, const SceneRegistry& scenes);

}  // namespace service::server
