#pragma once
// Mesh import: OBJ (+MTL, textures), PLY (ascii/binary, float/double), OFF, STL (ascii/binary),
// glTF 2.0 (.gltf/.glb, base-colour textures), CityJSON 0.x-2.0 (.city.json, .cityjson, and
// .json files whose content is CityJSON). Every failure is an Error naming the file and the
// problem (truncated, bad index, NaN coordinate, empty, unknown format); never a crash.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string_view>

#include "hlod/Mesh.h"
#include "hlod/Result.h"

namespace hlod {

// What a glTF scene may expand to: a node listed as the child of several parents is repeated
// under each, so a 1 KB file can name 2^40 instances. Past these bounds the import is an Error
// naming the bound, not an out-of-memory kill. Node instances: every node, once per path from a
// scene root to it. Scene elements: vertices (and, separately, triangles) of all mesh instances
// together, and the count of an accessor without a buffer view (one that no file bytes back).
inline constexpr std::uint64_t kMaxGltfNodeInstances = 1'000'000;
inline constexpr std::uint64_t kMaxGltfSceneElements = 100'000'000;

// The largest coordinate magnitude importModel accepts. Nodes store vertices in float relative
// to their centre, and a difference of two coordinates within this bound still fits a float
// (half of FLT_MAX); beyond it a build would write a store that reads back as corrupt.
inline constexpr double kMaxCoordinate = 1.7e38;

// CityJSON: at most this many triangles after geometry templates are instanced (a small file
// can instance a large template many times); past it the import is an Error.
inline constexpr std::uint64_t kMaxCityJsonTriangles = 100'000'000;

// What the caller chooses of a model with choices in it.
struct ImportOptions {
  // CityJSON: the level of detail to import, as the file writes it ("1", "2", "2.2"); city
  // objects without geometry at that LoD are left out. Empty: each city object at its highest.
  std::string lod;
};

// True when the extension is one importModel understands; a ".json" file is read to see whether
// it is CityJSON.
bool isMeshFile(const std::filesystem::path& path);

// Loads a mesh file into a Model (one Mesh per material/primitive group).
Result<Model> importModel(const std::filesystem::path& path, const ImportOptions& options = {});

// glTF 2.0 held in memory: a 3D Tiles content (a .glb, or the glTF inside a b3dm).
struct GltfBytes {
  std::filesystem::path name;  // for messages, as a file's path would be
  std::string_view bytes;
  bool binary = true;  // GLB, else glTF JSON
  // External buffers and images are looked up relative to baseDir and read only when they lie
  // inside `folder` (a tileset's folder).
  std::filesystem::path folder, baseDir;
  // Mesh::oneSided from the material's doubleSided flag (3D Tiles viewers cull the back faces
  // of single-sided materials, as glTF says); importModel draws every glTF mesh two-sided.
  bool oneSidedFromMaterial = false;
};
struct GltfContent {
  Model model;                          // may hold no mesh (points, lines, or nothing)
  std::optional<glm::dvec3> rtcCenter;  // the CESIUM_RTC extension's centre, when present
};
// Reads and checks as importModel does, except that a scene without triangles is not an error.
Result<GltfContent> importGltfBytes(const GltfBytes& in);

// Loads an image file (PNG, JPEG, ...) into RGBA8.
Result<Image> loadImage(const std::filesystem::path& path);

}  // namespace hlod
