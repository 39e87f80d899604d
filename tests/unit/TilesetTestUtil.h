#pragma once
// Hand-built 3D Tiles content for the tileset tests: a GLB of a few triangles, a b3dm around a
// GLB, and a tileset folder to write them into.
#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ImportTestUtil.h"
#include "hlod/Mesh.h"
#include "hlod/tiles/Glb.h"

namespace hlod::testing {

// A square of two triangles in glTF's frame (y up): x in [x0, x0 + size], z in [z0, z0 + size],
// at height y, facing up (a single-sided material unless twoSided); optionally with a texture.
inline std::string squareGlb(double x0, double z0, double y, double size,
                             std::shared_ptr<const Image> texture = nullptr,
                             glm::vec4 colour = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f),
                             bool twoSided = false) {
  LocalMesh m;
  m.centre = glm::dvec3(x0 + 0.5 * size, y, z0 + 0.5 * size);
  const float h = float(0.5 * size);
  // Counter-clockwise seen from +y: (-,+z) ... in glTF's x/z plane.
  m.positions = {{-h, 0, h}, {h, 0, h}, {h, 0, -h}, {-h, 0, -h}};
  m.normals.assign(4, glm::vec3(0, 1, 0));
  m.texCoords = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  m.baseColor = colour;
  m.texture = texture;
  m.oneSided = !twoSided;
  tiles::GlbContent c;
  c.mesh = &m;
  c.translation = m.centre;
  if (texture) {
    c.image.mimeType = "image/png";
    c.image.bytes = tiles::encodePng(*texture);
  }
  const std::vector<std::byte> glb = tiles::encodeGlb(c);
  return std::string(reinterpret_cast<const char*>(glb.data()), glb.size());
}

// A b3dm (3D Tiles 1.0) holding `glb`, with a feature table (padded to 8 bytes as the spec says)
// and an optional batch table.
inline std::string b3dm(const std::string& glb, const nlohmann::json& featureTable,
                        const std::string& featureBinary = {},
                        const nlohmann::json& batchTable = nullptr) {
  std::string ft = featureTable.dump();
  while ((28 + ft.size()) % 8) ft.push_back(' ');
  std::string fb = featureBinary;
  while (fb.size() % 8) fb.push_back('\0');
  std::string bt = batchTable.is_null() ? std::string() : batchTable.dump();
  while (bt.size() % 8) bt.push_back(' ');
  std::string out = "b3dm";
  const std::uint32_t length = std::uint32_t(28 + ft.size() + fb.size() + bt.size() + glb.size());
  putBytes(out, std::uint32_t(1));
  putBytes(out, length);
  putBytes(out, std::uint32_t(ft.size()));
  putBytes(out, std::uint32_t(fb.size()));
  putBytes(out, std::uint32_t(bt.size()));
  putBytes(out, std::uint32_t(0));
  return out + ft + fb + bt + glb;
}

// A tile with a box and content. Children in a vector: clang reads a json parameter given as
// {child} as a copy of child, gcc as an array of one.
inline nlohmann::json tile(const std::string& uri, double error,
                           std::vector<nlohmann::json> children = {}) {
  nlohmann::json t = {{"boundingVolume", {{"box", {0, 0, 0, 100, 0, 0, 0, 100, 0, 0, 0, 100}}}},
                      {"geometricError", error}};
  if (!uri.empty()) t["content"] = {{"uri", uri}};
  if (!children.empty()) t["children"] = std::move(children);
  return t;
}

inline nlohmann::json tileset(nlohmann::json root, const std::string& version = "1.1") {
  root["refine"] = root.value("refine", std::string("REPLACE"));
  return {{"asset", {{"version", version}}}, {"geometricError", 1000.0}, {"root", std::move(root)}};
}

}  // namespace hlod::testing
