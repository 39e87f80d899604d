#include "service/SceneLoading.h"

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "hlod/City.h"
#include "hlod/Import.h"
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
    scene.up = {0.0, 0.0, 1.0};
    return scene;
  }
  if (std::filesystem::is_directory(path, ec))
    return hlod::makeError(path.string() + ": a folder but not a city (no city.json)");
  auto model = hlod::importModel(path, options);
  if (!model) return model.error();
  for (const auto& w : model->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  scene.up = model->zUp ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(0.0, 1.0, 0.0);
  scene.model = std::move(*model);
  return scene;
}

CameraPose defaultCamera(const hlod::Aabb& bounds, const glm::dvec3& up, double fovY,
                         double aspect) {
  CameraPose cam;
  cam.up = up;
  cam.fovY = fovY;
  cam.target = bounds.centre();
  const double radius = std::max(glm::length(bounds.size()) * 0.5, 1e-6);
  // A three-quarter view from above: most of the model shows, and so do its facades.
  const glm::dvec3 dir = up.z > 0.5 ? glm::normalize(glm::dvec3(-0.55, -1.0, 0.8))
                                    : glm::normalize(glm::dvec3(0.6, 0.55, 1.0));
  // Tightest distance along dir at which all eight corners of the box lie inside the frustum:
  // a corner r (relative to the target) at lateral offsets x, y and depth d - r.dir needs
  // d >= r.dir + |x| / tan(halfFovX) and d >= r.dir + |y| / tan(halfFovY).
  const double tanY = std::tan(glm::radians(fovY) * 0.5), tanX = tanY * aspect;
  glm::dvec3 right = glm::cross(-dir, up);
  right = glm::length(right) > 1e-9 ? glm::normalize(right) : glm::dvec3(1, 0, 0);
  const glm::dvec3 upView = glm::cross(right, -dir);
  double distance = radius * 1e-3;
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 corner((i & 1) ? bounds.max.x : bounds.min.x,
                            (i & 2) ? bounds.max.y : bounds.min.y,
                            (i & 4) ? bounds.max.z : bounds.min.z);
    const glm::dvec3 r = corner - cam.target;
    const double along = glm::dot(r, dir);
    distance = std::max({distance, along + std::abs(glm::dot(r, right)) / tanX,
                         along + std::abs(glm::dot(r, upView)) / tanY});
  }
  distance *= 1.05;  // a small margin
  cam.position = cam.target + dir * distance;
  return cam;
}

void clipPlanes(const CameraPose& camera, const hlod::Aabb& bounds, double& zNear, double& zFar) {
  renderer::clipPlanesFor(camera.position, bounds, zNear, zFar);
}

}  // namespace service
