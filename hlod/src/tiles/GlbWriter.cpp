// encodeGlb: a node's mesh as binary glTF 2.0 (the "Binary glTF Layout" of the glTF 2.0
// specification); encodePng, encodeJpeg: its texture. See hlod/tiles/Glb.h.
#include <stb_image_write.h>

#include <algorithm>
#include <cassert>
#include <cstring>

#include "hlod/tiles/Glb.h"

namespace hlod::tiles {

AxisMap AxisMap::then(const AxisMap& next) const {
  AxisMap out;
  for (int k = 0; k < 3; ++k) {
    out.axis[k] = axis[next.axis[k]];
    out.sign[k] = next.sign[k] * sign[next.axis[k]];
  }
  return out;
}

AxisMap AxisMap::inverse() const {
  AxisMap out;
  for (int k = 0; k < 3; ++k) {
    out.axis[axis[k]] = k;
    out.sign[axis[k]] = sign[k];
  }
  return out;
}

glm::dmat3 AxisMap::matrix() const {
  glm::dmat3 m(0.0);
  for (int k = 0; k < 3; ++k) m[axis[k]][k] = sign[k];  // row k, column axis[k]
  return m;
}

namespace {

// glTF constants (glTF 2.0 specification, sec. 5: accessor component types, buffer view targets,
// sampler filters and wraps).
constexpr int kFloat = 5126;
constexpr int kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;
constexpr int kLinear = 9729;
constexpr int kLinearMipmapLinear = 9987;
constexpr int kRepeat = 10497;
constexpr int kTriangles = 4;

template <class T>
void appendBytes(std::vector<std::byte>& out, const T* data, std::size_t count) {
  const auto* p = reinterpret_cast<const std::byte*>(data);
  out.insert(out.end(), p, p + count * sizeof(T));
}

void appendU32(std::vector<std::byte>& out, std::uint32_t v) {
  appendBytes(out, &v, 1);
}

void padTo4(std::vector<std::byte>& bytes, std::byte fill) {
  while (bytes.size() % 4 != 0) bytes.push_back(fill);
}

void writeToVector(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(context);
  const auto* p = static_cast<const std::uint8_t*>(data);
  out->insert(out->end(), p, p + size);
}

}  // namespace

std::vector<std::byte> encodeGlb(const GlbContent& content) {
  assert(content.mesh && content.mesh->triangleCount() > 0);
  const LocalMesh& mesh = *content.mesh;
  const std::size_t n = mesh.positions.size();
  const bool uv = mesh.texCoords.size() == n && n > 0;
  const bool textured =
      uv && mesh.texture && (!content.image.bytes.empty() || !content.image.uri.empty());
  std::vector<std::byte> bin;
  nlohmann::json views = nlohmann::json::array(), accessors = nlohmann::json::array();
  auto view = [&](std::size_t offset, int target) {
    nlohmann::json v = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bin.size() - offset}};
    if (target) v["target"] = target;
    views.push_back(v);
    return int(views.size() - 1);
  };
  nlohmann::json attributes;

  // Positions and normals through the axis change: a permutation with signs, exact in float.
  std::vector<glm::vec3> buffer(n);
  glm::vec3 lo(0.0f), hi(0.0f);
  for (std::size_t i = 0; i < n; ++i) {
    buffer[i] = content.toGltf.apply(mesh.positions[i]);
    lo = i ? glm::min(lo, buffer[i]) : buffer[i];
    hi = i ? glm::max(hi, buffer[i]) : buffer[i];
  }
  std::size_t at = bin.size();
  appendBytes(bin, buffer.data(), n);
  accessors.push_back({{"bufferView", view(at, kArrayBuffer)},
                       {"componentType", kFloat},
                       {"count", n},
                       {"type", "VEC3"},
                       {"min", {lo.x, lo.y, lo.z}},
                       {"max", {hi.x, hi.y, hi.z}}});
  attributes["POSITION"] = accessors.size() - 1;
  if (mesh.normals.size() == n) {
    for (std::size_t i = 0; i < n; ++i) buffer[i] = content.toGltf.apply(mesh.normals[i]);
    at = bin.size();
    appendBytes(bin, buffer.data(), n);
    accessors.push_back({{"bufferView", view(at, kArrayBuffer)},
                         {"componentType", kFloat},
                         {"count", n},
                         {"type", "VEC3"}});
    attributes["NORMAL"] = accessors.size() - 1;
  }
  if (uv) {
    at = bin.size();
    appendBytes(bin, mesh.texCoords.data(), n);
    accessors.push_back({{"bufferView", view(at, kArrayBuffer)},
                         {"componentType", kFloat},
                         {"count", n},
                         {"type", "VEC2"}});
    attributes["TEXCOORD_0"] = accessors.size() - 1;
  }
  at = bin.size();
  appendBytes(bin, mesh.indices.data(), mesh.indices.size());
  accessors.push_back({{"bufferView", view(at, kElementArrayBuffer)},
                       {"componentType", kUnsignedInt},
                       {"count", mesh.indices.size()},
                       {"type", "SCALAR"}});
  const std::size_t indexAccessor = accessors.size() - 1;

  const glm::vec4& c = mesh.baseColor;
  nlohmann::json pbr = {
      {"baseColorFactor", {c.r, c.g, c.b, c.a}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}};
  nlohmann::json gltf;
  if (textured) {
    pbr["baseColorTexture"] = {{"index", 0}};
    // Mipmapped and repeating: as hlodr's renderer samples node textures.
    gltf["samplers"] = {{{"magFilter", kLinear},
                         {"minFilter", kLinearMipmapLinear},
                         {"wrapS", kRepeat},
                         {"wrapT", kRepeat}}};
    gltf["textures"] = {{{"sampler", 0}, {"source", 0}}};
    nlohmann::json image;
    if (!content.image.bytes.empty()) {
      at = bin.size();
      appendBytes(bin, content.image.bytes.data(), content.image.bytes.size());
      image = {{"bufferView", view(at, 0)}, {"mimeType", content.image.mimeType}};
      padTo4(bin, std::byte{0});
    } else {
      image = {{"uri", content.image.uri}};
    }
    gltf["images"] = nlohmann::json::array({image});
  }
  gltf["asset"] = {{"version", "2.0"}, {"generator", "hlodr"}};
  gltf["scene"] = 0;
  gltf["scenes"] = {{{"nodes", {0}}}};
  nlohmann::json node = {
      {"mesh", 0},
      {"translation", {content.translation.x, content.translation.y, content.translation.z}}};
  if (!content.extras.is_null()) node["extras"] = content.extras;
  gltf["nodes"] = nlohmann::json::array({node});
  gltf["materials"] = {{{"pbrMetallicRoughness", pbr}, {"doubleSided", !mesh.oneSided}}};
  gltf["meshes"] = {{{"primitives",
                      {{{"attributes", attributes},
                        {"indices", indexAccessor},
                        {"material", 0},
                        {"mode", kTriangles}}}}}};
  gltf["buffers"] = {{{"byteLength", bin.size()}}};
  gltf["bufferViews"] = views;
  gltf["accessors"] = accessors;

  std::string json = gltf.dump();
  while (json.size() % 4 != 0) json.push_back(' ');
  padTo4(bin, std::byte{0});
  std::vector<std::byte> out;
  const std::size_t total = 12 + 8 + json.size() + 8 + bin.size();
  out.reserve(total);
  appendU32(out, 0x46546C67u);  // "glTF"
  appendU32(out, 2);
  appendU32(out, std::uint32_t(total));
  appendU32(out, std::uint32_t(json.size()));
  appendU32(out, 0x4E4F534Au);  // "JSON"
  appendBytes(out, json.data(), json.size());
  appendU32(out, std::uint32_t(bin.size()));
  appendU32(out, 0x004E4942u);  // "BIN\0"
  out.insert(out.end(), bin.begin(), bin.end());
  return out;
}

std::vector<std::uint8_t> encodePng(const Image& image) {
  assert(!image.empty());
  const std::size_t count = std::size_t(image.width) * std::size_t(image.height);
  bool opaque = true;
  for (std::size_t i = 0; i < count && opaque; ++i) opaque = image.pixels[4 * i + 3] == 255;
  std::vector<std::uint8_t> rgb;
  const std::uint8_t* pixels = image.pixels.data();
  int channels = 4;
  if (opaque) {
    rgb.resize(count * 3);
    for (std::size_t i = 0; i < count; ++i) std::memcpy(&rgb[3 * i], &image.pixels[4 * i], 3);
    pixels = rgb.data();
    channels = 3;
  }
  std::vector<std::uint8_t> out;
  stbi_write_png_to_func(writeToVector, &out, image.width, image.height, channels, pixels,
                         image.width * channels);
  return out;
}

std::vector<std::uint8_t> encodeJpeg(const Image& image, int quality) {
  assert(!image.empty());
  std::vector<std::uint8_t> out;
  stbi_write_jpg_to_func(writeToVector, &out, image.width, image.height, 4, image.pixels.data(),
                         std::clamp(quality, 1, 100));
  return out;
}

}  // namespace hlod::tiles
