#pragma once
// The colours CityJSON surfaces get from their semantics, when no material of the file's
// `appearance` colours them (a material's diffuseColor wins):
//   RoofSurface    red-brown   (0.62, 0.27, 0.20)
//   WallSurface    light beige (0.86, 0.83, 0.76)
//   GroundSurface  dark grey   (0.30, 0.30, 0.30)
//   any other      neutral     (0.68, 0.68, 0.68)  (doors, windows, closures, no semantics ...)
#include <string_view>

#include <glm/glm.hpp>

namespace hlod {

enum class SurfaceClass { Roof, Wall, Ground, Other };

SurfaceClass surfaceClass(std::string_view semanticType);
glm::vec4 surfaceColour(SurfaceClass c);
const char* surfaceClassName(SurfaceClass c);  // "roof", "wall", "ground", "other"

}  // namespace hlod
