#pragma once
// A glTF 2.0 binary (GLB) writer for scenes of instanced meshes with flat materials: what `hlodr
// plant` writes. One buffer in the BIN chunk (per mesh: positions and normals as float VEC3,
// indices as unsigned short or int), one accessor per attribute with the min/max the
// specification requires for positions, PBR materials of a base colour, metallic and roughness
// factor each, and nodes that name a mesh with a translation, rotation and scale, or only children
// (a scene organised by function). The bytes depend only on the scene: the same scene writes the
// same file.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "hlod/Result.h"

namespace hlod {

struct GltfMaterial {
  std::string name;
  glm::vec4 baseColor{0.8f, 0.8f, 0.8f, 1.0f};
  float metallic = 0.0f;
  float roughness = 0.8f;
};

struct GltfMesh {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // one per position, unit length
  std::vector<std::uint32_t> indices;
  std::uint32_t material = 0;
};

struct GltfNode {
  std::string name;
  std::int32_t mesh = -1;  // -1: a group (its children only)
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};  // (w, x, y, z), unit
  glm::dvec3 scale{1.0};
  std::vector<std::uint32_t> children;
};

struct GltfScene {
  std::vector<GltfMaterial> materials;
  std::vector<GltfMesh> meshes;
  std::vector<GltfNode> nodes;
  std::vector<std::uint32_t> roots;  // the scene's nodes
  std::string generator = "hlodr";
  std::string copyright;
};

// The scene as GLB bytes; an Error past the 4 GB a GLB holds. Asserts what the scene's maker
// must keep: meshes with vertices, indices within their mesh, material, mesh and child indices
// in range, a normal per position.
Result<std::string> encodeGlb(const GltfScene& scene);
// encodeGlb to a file; an Error when it cannot be written.
Status writeGlb(const GltfScene& scene, const std::filesystem::path& path);

}  // namespace hlod
