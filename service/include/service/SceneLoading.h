#pragma once
// Loads what `hlodr render` is given: a mesh file or a city folder, into a Model; and picks a
// default camera that frames it.
#include <filesystem>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "hlod/UpAxis.h"
#include "hlod/import/Import.h"
#include "hlod/runtime/Camera.h"
#include "hlod/store/Skeleton.h"
#include "renderer/FrameView.h"

namespace service {

struct LoadedScene {
  hlod::Model model;
  hlod::UpAxis up = hlod::UpAxis::Z;  // hlod::upAxisOf the model; a city folder is Z-up
  bool isCity = false;
};

// options: what importModel is to choose (CityJSON's LoD); a city folder has no choices.
hlod::Result<LoadedScene> loadScene(const std::filesystem::path& path, bool quiet,
                                    const hlod::ImportOptions& options = {});

struct CameraPose {
  glm::dvec3 position{0.0};
  glm::dvec3 target{0.0};
  glm::dvec3 up{0.0, 0.0, 1.0};
  double fovY = 50.0;  // degrees
};

// The default view of a model (hlod::defaultViewDirection, framed by hlod::frameBounds).
CameraPose defaultCamera(const hlod::Aabb& bounds, hlod::UpAxis up, double fovY, double aspect);

// The default camera of a node store: the box of its roots, framed as defaultCamera frames a
// model (the server's scenes and `hlodr render STORE` start from it).
hlod::Camera storeCamera(const hlod::Skeleton& skeleton, double fovY, double aspect);

// Near and far planes that hold the box seen from the camera (reversed-Z makes a wide range safe).
void clipPlanes(const CameraPose& camera, const hlod::Aabb& bounds, double& zNear, double& zFar);

}  // namespace service
