#pragma once
// A scene file (JSON, docs/scene.md): the model store, camera defaults, the background and the
// effects the scene calls for. Every effect is off unless declared: the renderer compiles and
// runs only what is here, and the loader reads only the data it needs (no textures: no texture
// bytes). Parsing is pure (no GL): it validates once, here, and the rest of hlodr trusts it.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Result.h"

namespace hlod {

enum class Shading { Unlit, Lambert, BlinnPhong };

// A directional light: `direction` points towards the sun (world space, unit length).
struct SunLight {
  glm::dvec3 direction = glm::normalize(glm::dvec3(0.45, -0.35, 0.82));
  glm::vec3 colour{1.0f, 0.96f, 0.88f};
  float intensity = 1.0f;
};

// Exponential distance fog towards the background's horizon colour: a fragment at distance d
// keeps exp(-density d) of its colour. density 0: derived from the view distance each frame,
// 1 / far (far: the frame's far plane, past the far side of the model), so the farthest geometry
// keeps at least 37% of its colour whatever the model's size.
struct FogEffect {
  double density = 0.0;
};

// A shadow map from the sun, fitted to the drawn front's bounding sphere.
struct ShadowEffect {
  int resolution = 2048;  // texels per side
};

// Screen-space ambient occlusion from the depth buffer, blurred, multiplied into the colour.
struct SsaoEffect {
  double radius = 2.0;  // world units
  int samples = 12;
  float strength = 1.0f;
};

// Edges where depth jumps (silhouettes, creases of CAD models) drawn in a colour.
struct OutlineEffect {
  glm::vec3 colour{0.05f, 0.05f, 0.05f};
  float thickness = 1.0f;   // pixels
  float threshold = 0.02f;  // relative depth jump that counts as an edge
};

struct Background {
  bool sky = false;  // a vertical gradient horizon -> zenith; otherwise a flat colour
  glm::vec3 colour{0.70f, 0.80f, 0.90f};  // flat colour, and the sky's horizon colour
  glm::vec3 zenith{0.28f, 0.50f, 0.85f};
  glm::vec3 ground{0.55f, 0.55f, 0.52f};  // below the horizon
  glm::vec3 horizon() const { return colour; }
};

struct SceneEffects {
  bool textures = false;
  Shading shading = Shading::Unlit;
  std::optional<SunLight> sun;
  std::optional<FogEffect> fog;
  std::optional<ShadowEffect> shadows;
  std::optional<SsaoEffect> ssao;
  std::optional<OutlineEffect> outline;
  Background background;

  bool lit() const { return shading != Shading::Unlit; }
};

// What `hlodr render` draws when no scene is given: textures and lambert shading under the
// default sun, flat background (the behaviour before scene files).
SceneEffects defaultEffects();

struct SceneCamera {
  glm::dvec3 position{0.0};
  glm::dvec3 target{0.0};
  std::optional<glm::dvec3> up;
  double fov = 50.0;  // vertical, degrees
};

struct SceneFile {
  std::string store;  // the node store, as written in the file ("" when not given)
  std::optional<SceneCamera> camera;
  SceneEffects effects;
};

// The effect names a scene may declare, in the order docs/scene.md lists them.
const std::vector<std::string>& knownEffects();

// What a scene turns on, for people: the shading's name unless unlit, then "textures", "sun",
// "sky", "fog", "shadows", "ssao", "outline" where declared (the page's scene picker shows it).
std::vector<std::string> declaredEffects(const SceneEffects& effects);

// Parses a scene from JSON text. Errors name the field ("effects.fog.density: must be a number
// in 0..1 (got -1)"); an unknown effect lists the known ones.
Result<SceneFile> parseScene(const std::string& text);
// Reads and parses a file; errors start with the file's name.
Result<SceneFile> readSceneFile(const std::filesystem::path& path);

// The density a frame uses: the declared one, or derived from the far distance (see FogEffect).
double fogDensityFor(const FogEffect& fog, double farDistance);
// The distance beyond which fog hides everything in 8-bit colour: exp(-density d) < 1/510, so the
// blended colour rounds to the fog colour. Nodes wholly beyond it are culled (as Cesium culls
// tiles whose fog factor reaches 1).
double fogCullDistance(double density);

}  // namespace hlod
