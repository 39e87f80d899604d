#include "hlod/import/CityJsonPalette.h"

namespace hlod {

SurfaceClass surfaceClass(std::string_view type) {
  if (type == "RoofSurface") return SurfaceClass::Roof;
  if (type == "WallSurface") return SurfaceClass::Wall;
  if (type == "GroundSurface") return SurfaceClass::Ground;
  return SurfaceClass::Other;
}

glm::vec4 surfaceColour(SurfaceClass c) {
  switch (c) {
    case SurfaceClass::Roof:
      return {0.62f, 0.27f, 0.20f, 1.0f};
    case SurfaceClass::Wall:
      return {0.86f, 0.83f, 0.76f, 1.0f};
    case SurfaceClass::Ground:
      return {0.30f, 0.30f, 0.30f, 1.0f};
    case SurfaceClass::Other:
      break;
  }
  return {0.68f, 0.68f, 0.68f, 1.0f};
}

const char* surfaceClassName(SurfaceClass c) {
  switch (c) {
    case SurfaceClass::Roof:
      return "roof";
    case SurfaceClass::Wall:
      return "wall";
    case SurfaceClass::Ground:
      return "ground";
    case SurfaceClass::Other:
      break;
  }
  return "other";
}

}  // namespace hlod
