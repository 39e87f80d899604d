#pragma once
// One node's content as binary glTF 2.0 (GLB): the container of the glTF 2.0 specification,
// sec. "Binary glTF Layout" (KhronosGroup/glTF, specification/2.0): a 12-byte header (magic
// "glTF", version 2, total length), a JSON chunk padded with spaces and a BIN chunk padded with
// zeros, each to 4 bytes.
//
// The mesh is one triangle primitive: POSITION (with its min and max, as glTF requires), NORMAL,
// TEXCOORD_0 when the node has texture coordinates, and 32-bit indices in the node's triangle
// order, under one node whose translation is the node's centre (relative-to-centre positions:
// float offsets from a double centre, as the node store keeps them). The material is the node's
// base colour and texture; doubleSided is the opposite of LocalMesh::oneSided.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "hlod/Mesh.h"

namespace hlod::tiles {

// An axis change that loses nothing: glTF component k is sign[k] * the local component axis[k]
// (a rotation or reflection that only permutes and negates, so float values stay exact).
struct AxisMap {
  int axis[3] = {0, 1, 2};
  float sign[3] = {1.0f, 1.0f, 1.0f};

  glm::vec3 apply(const glm::vec3& v) const {
    return {sign[0] * v[axis[0]], sign[1] * v[axis[1]], sign[2] * v[axis[2]]};
  }
  glm::dvec3 apply(const glm::dvec3& v) const {
    return {sign[0] * v[axis[0]], sign[1] * v[axis[1]], sign[2] * v[axis[2]]};
  }
  AxisMap then(const AxisMap& next) const;  // next after this
  AxisMap inverse() const;
  glm::dmat3 matrix() const;  // the same as a matrix (columns as glm stores them)
};

// The node's texture: embedded in the GLB (image bytes), referred to by a URI relative to the
// GLB (a texture several nodes share, written once beside them), or none.
struct GlbImage {
  std::string mimeType;             // "image/png" or "image/jpeg"
  std::vector<std::uint8_t> bytes;  // embedded, when not empty
  std::string uri;                  // external, when not empty
};

struct GlbContent {
  const LocalMesh* mesh = nullptr;
  AxisMap toGltf;               // from the mesh's frame into glTF's (y up)
  glm::dvec3 translation{0.0};  // the node's centre in glTF's frame
  GlbImage image;               // used when mesh->texture is set
  nlohmann::json extras;        // the glTF node's extras (null: none)
};

// The GLB bytes. mesh must hold at least one triangle and indices below its vertex count.
std::vector<std::byte> encodeGlb(const GlbContent& content);

// PNG (lossless; RGB when every pixel is opaque) or JPEG (quality 1..100) bytes of an image.
std::vector<std::uint8_t> encodePng(const Image& image);
std::vector<std::uint8_t> encodeJpeg(const Image& image, int quality);

}  // namespace hlod::tiles
