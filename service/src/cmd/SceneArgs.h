#pragma once
// The effects of a render: a scene file (--scene FILE) or the older flags (--unlit,
// --no-textures, --fog), not both.
#include <optional>

#include "hlod/scene/SceneFile.h"
#include "service/Args.h"

namespace service::cmd {

struct SceneArgs {
  hlod::SceneFile scene;  // effects from the file, or the flags over defaultEffects()
  bool fromFile = false;
  std::filesystem::path file;
};

// up: the model's up axis (the default sun is placed above it).
hlod::Result<SceneArgs> sceneFromArgs(const Args& args, const glm::dvec3& up);

}  // namespace service::cmd
