#include "cmd/SceneArgs.h"

namespace service::cmd {

hlod::Result<SceneArgs> sceneFromArgs(const Args& args, const glm::dvec3& up) {
  SceneArgs out;
  if (auto file = args.get("scene")) {
    for (const char* flag : {"unlit", "no-textures", "fog"})
      if (args.has(flag))
        return hlod::makeError("--" + std::string(flag) +
                               " and --scene: the scene file declares the effects");
    auto scene = hlod::readSceneFile(*file);
    if (!scene) return scene.error();
    out.scene = std::move(*scene);
    out.fromFile = true;
    out.file = *file;
    return out;
  }
  out.scene.effects = hlod::defaultEffects();
  // Mesh files are Y-up: the default sun stands above them too.
  if (up.z < 0.5) out.scene.effects.sun->direction = glm::normalize(glm::dvec3(0.45, 0.82, 0.35));
  if (args.has("unlit")) out.scene.effects.shading = hlod::Shading::Unlit;
  out.scene.effects.textures = !args.has("no-textures");
  if (args.has("fog")) out.scene.effects.fog = hlod::FogEffect{};
  return out;
}

}  // namespace service::cmd
