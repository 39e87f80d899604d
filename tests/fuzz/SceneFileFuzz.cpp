// Scene files (docs/scene.md, `hlodr render --scene`, a request's inline scene): the input is
// the JSON text. A scene that parses must hold what the renderer and loader trust without
// checking again: finite camera values with position and target apart, unit sun and up
// vectors, colours in 0..1, every effect's settings in their documented ranges; and a camera
// made from it must give a finite view frame.
#include <cmath>
#include <cstdlib>

#include "FuzzSupport.h"
#include "hlod/runtime/Camera.h"
#include "hlod/scene/SceneFile.h"

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

bool unit(const glm::dvec3& v) {
  return finite(v) && std::abs(glm::length(v) - 1.0) < 1e-6;
}

bool colour(const glm::vec3& c) {
  for (int i = 0; i < 3; ++i)
    if (!(c[i] >= 0.0f && c[i] <= 1.0f)) return false;
  return true;
}

void checkScene(const hlod::SceneFile& s) {
  if (const auto& c = s.camera) {
    check(finite(c->position) && finite(c->target) && c->position != c->target);
    check(c->fov >= 1.0 && c->fov <= 170.0);
    if (c->up) check(unit(*c->up));
    hlod::Camera cam;
    cam.position = c->position;
    cam.target = c->target;
    cam.up = c->up.value_or(cam.up);
    cam.fovY = c->fov;
    check(finite(cam.forward()) && finite(cam.right()) && finite(cam.trueUp()));
  }
  const auto& e = s.effects;
  if (e.sun)
    check(unit(e.sun->direction) && colour(e.sun->colour) && e.sun->intensity >= 0.0f &&
          e.sun->intensity <= 10.0f);
  if (e.fog) check(e.fog->density >= 0.0 && e.fog->density <= 1.0);
  if (e.shadows) check(e.shadows->resolution >= 256 && e.shadows->resolution <= 8192);
  if (e.ssao)
    check(e.ssao->radius > 0.0 && std::isfinite(e.ssao->radius) && e.ssao->samples >= 4 &&
          e.ssao->samples <= 64 && e.ssao->strength >= 0.0f && e.ssao->strength <= 4.0f);
  if (e.outline)
    check(colour(e.outline->colour) && e.outline->thickness >= 0.5f &&
          e.outline->thickness <= 8.0f && e.outline->threshold > 0.0f &&
          e.outline->threshold <= 1.0f);
  check(colour(e.background.colour) && colour(e.background.zenith) && colour(e.background.ground));
  if (e.fog) {
    const double density = hlod::fogDensityFor(*e.fog, 1000.0);
    check(std::isfinite(density) && density >= 0.0);
    check(!std::isnan(hlod::fogCullDistance(density)));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto scene = hlod::parseScene(std::string(fuzz::view(data, size)));
  fuzz::report("parseScene", scene);
  if (scene.ok()) checkScene(*scene);
  return 0;
}
