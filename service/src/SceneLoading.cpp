#include "service/SceneLoading.h"

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "hlod/city/City.h"
#include "hlod/import/Import.h"
#include "hlod/runtime/Framing.h"
#include "renderer/GpuNodeRenderer.h"

namespace service {

hlod::Result<LoadedScene> loadScene(const std::filesystem::path& path, bool quiet,
                                    const hlod::ImportOptions& options) {
  LoadedScene scene;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    return hlod::makeError(path.string() + ": no such file or folder");
  if (hlod::isCityFolder(path)) {
    auto manifest = hlod::readCityManifest(path);
    if (!manifest) return manifest.error();
    const bool progress = !quiet && isatty(STDERR_FILENO);
    for (std::size_t i = 0; i < manifest->blocks.size(); ++i) {
      auto block = hlod::loadCityBlock(*manifest, i);
      if (!block) return block.error();
      scene.model.meshes.push_back(std::move(*block));
      if (progress)
        std::fprintf(stderr, "\rloading city: block %zu/%zu", i + 1, manifest->blocks.size());
    }
    if (progress) std::fprintf(stderr, "\n");
    scene.isCity = true;
    scene.up = hlod::UpAxis::Z;
    return scene;
  }
  if (std::filesystem::is_directory(path, ec))
    return hlod::makeError(path.string() + ": a folder but not a city (no city.json)");
  auto model = hlod::importModel(path, options);
  if (!model) return model.error();
  for (const auto& w : model->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  scene.up = hlod::upAxisOf(*model);
  scene.model = std::move(*model);
  return scene;
}

CameraPose defaultCamera(const hlod::Aabb& bounds, hlod::UpAxis up, double fovY, double aspect) {
  const hlod::Camera framed = hlod::defaultView(bounds, up, fovY, aspect);
  CameraPose cam;
  cam.position = framed.position;
  cam.target = framed.target;
  cam.up = framed.up;
  cam.fovY = framed.fovY;
  return cam;
}

hlod::Camera storeCamera(const hlod::Skeleton& skeleton, double fovY, double aspect) {
  hlod::Aabb bounds;
  for (std::uint32_t r : skeleton.roots) bounds.extend(skeleton.nodes[r].bounds);
  const CameraPose pose = defaultCamera(bounds, skeleton.up, fovY, aspect);
  hlod::Camera c;
  c.position = pose.position;
  c.target = pose.target;
  c.up = pose.up;
  c.fovY = pose.fovY;
  c.aspect = aspect;
  return c;
}

void clipPlanes(const CameraPose& camera, const hlod::Aabb& bounds, double& zNear, double& zFar) {
  renderer::clipPlanesFor(camera.position, bounds, zNear, zFar);
}

}  // namespace service
