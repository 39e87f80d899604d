// The GLB writer (hlod/plant/GlbWriter.h). The layout is the glTF 2.0 specification's binary
// container: a 12-byte header ("glTF", version 2, total length), a JSON chunk padded with spaces
// to 4 bytes, then a BIN chunk padded with zeros; every buffer view starts on a 4-byte boundary.
#include "hlod/plant/GlbWriter.h"

#include <algorithm>
#include <cassert>
#include <cstring>
#include <fstream>

#include <nlohmann/json.hpp>

namespace hlod {

namespace {

constexpr int kFloat = 5126, kUnsignedShort = 5123, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

void put32(std::string& s, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) s.push_back(char((v >> (8 * k)) & 0xff));
}

template <class T>
void putRaw(std::string& s, const T* data, std::size_t count) {
  // Little-endian hosts only (as every reader of hlodr's stores assumes).
  s.append(reinterpret_cast<const char*>(data), count * sizeof(T));
}

void pad(std::string& s, char with) {
  while (s.size() % 4) s.push_back(with);
}

}  // namespace

Result<std::string> encodeGlb(const GltfScene& scene) {
  using nlohmann::json;
  std::string bin;
  json bufferViews = json::array(), accessors = json::array(), meshes = json::array();
  const auto view = [&](std::size_t offset, std::size_t length, int target) {
    bufferViews.push_back(
        {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}, {"target", target}});
    return bufferViews.size() - 1;
  };
  for (const GltfMesh& m : scene.meshes) {
    assert(!m.positions.empty() && m.normals.size() == m.positions.size() &&
           m.material < scene.materials.size());
    glm::vec3 lo(0.0f), hi(0.0f);
    if (!m.positions.empty()) lo = hi = m.positions.front();
    for (const glm::vec3& p : m.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    std::size_t at = bin.size();
    putRaw(bin, &m.positions[0].x, m.positions.size() * 3);
    const std::size_t positions = view(at, bin.size() - at, kArrayBuffer);
    at = bin.size();
    putRaw(bin, &m.normals[0].x, m.normals.size() * 3);
    const std::size_t normals = view(at, bin.size() - at, kArrayBuffer);
    at = bin.size();
    const bool shortIndices = m.positions.size() <= 65536;
    if (shortIndices) {
      for (std::uint32_t i : m.indices) {
        assert(i < m.positions.size());
        const auto s = std::uint16_t(i);
        putRaw(bin, &s, 1);
      }
    } else {
      assert(std::all_of(m.indices.begin(), m.indices.end(),
                         [&](std::uint32_t i) { return i < m.positions.size(); }));
      putRaw(bin, m.indices.data(), m.indices.size());
    }
    const std::size_t indices = view(at, bin.size() - at, kElementArrayBuffer);
    pad(bin, '\0');
    const std::size_t first = accessors.size();
    accessors.push_back({{"bufferView", positions},
                         {"componentType", kFloat},
                         {"count", m.positions.size()},
                         {"type", "VEC3"},
                         {"min", {lo.x, lo.y, lo.z}},
                         {"max", {hi.x, hi.y, hi.z}}});
    accessors.push_back({{"bufferView", normals},
                         {"componentType", kFloat},
                         {"count", m.normals.size()},
                         {"type", "VEC3"}});
    accessors.push_back({{"bufferView", indices},
                         {"componentType", shortIndices ? kUnsignedShort : kUnsignedInt},
                         {"count", m.indices.size()},
                         {"type", "SCALAR"}});
    meshes.push_back({{"name", m.name},
                      {"primitives",
                       {{{"attributes", {{"POSITION", first}, {"NORMAL", first + 1}}},
                         {"indices", first + 2},
                         {"material", m.material},
                         {"mode", 4}}}}});
  }
  json materials = json::array();
  for (const GltfMaterial& m : scene.materials)
    materials.push_back(
        {{"name", m.name},
         {"pbrMetallicRoughness",
          {{"baseColorFactor", {m.baseColor.r, m.baseColor.g, m.baseColor.b, m.baseColor.a}},
           {"metallicFactor", m.metallic},
           {"roughnessFactor", m.roughness}}}});
  json nodes = json::array();
  for (const GltfNode& n : scene.nodes) {
    json node = {{"name", n.name}};
    if (n.mesh >= 0) {
      assert(std::size_t(n.mesh) < scene.meshes.size());
      node["mesh"] = n.mesh;
    }
    if (n.translation != glm::dvec3(0.0))
      node["translation"] = {n.translation.x, n.translation.y, n.translation.z};
    if (n.rotation != glm::dquat(1.0, 0.0, 0.0, 0.0))
      node["rotation"] = {n.rotation.x, n.rotation.y, n.rotation.z, n.rotation.w};
    if (n.scale != glm::dvec3(1.0)) node["scale"] = {n.scale.x, n.scale.y, n.scale.z};
    if (!n.children.empty()) {
      assert(std::all_of(n.children.begin(), n.children.end(),
                         [&](std::uint32_t c) { return c < scene.nodes.size(); }));
      node["children"] = n.children;
    }
    nodes.push_back(std::move(node));
  }
  json asset = {{"version", "2.0"}, {"generator", scene.generator}};
  if (!scene.copyright.empty()) asset["copyright"] = scene.copyright;
  json gltf = {{"asset", asset},
               {"scene", 0},
               {"scenes", {{{"nodes", scene.roots}}}},
               {"nodes", nodes},
               {"meshes", meshes},
               {"materials", materials},
               {"accessors", accessors},
               {"bufferViews", bufferViews},
               {"buffers", {{{"byteLength", bin.size()}}}}};
  std::string text = gltf.dump();
  pad(text, ' ');
  if (28 + text.size() + bin.size() > 0xffffffffull)
    return makeError("the scene takes more than the 4 GB a GLB file can hold");
  std::string out;
  out.reserve(28 + text.size() + bin.size());
  put32(out, 0x46546C67);  // "glTF"
  put32(out, 2);
  put32(out, std::uint32_t(12 + 8 + text.size() + 8 + bin.size()));
  put32(out, std::uint32_t(text.size()));
  put32(out, 0x4E4F534A);  // "JSON"
  out += text;
  put32(out, std::uint32_t(bin.size()));
  put32(out, 0x004E4942);  // "BIN\0"
  out += bin;
  return out;
}

Status writeGlb(const GltfScene& scene, const std::filesystem::path& path) {
  const Result<std::string> bytes = encodeGlb(scene);
  if (!bytes) return makeError(path.string() + ": " + bytes.message());
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return makeError(path.string() + ": cannot be written");
  f.write(bytes->data(), std::streamsize(bytes->size()));
  f.close();
  if (!f) return makeError(path.string() + ": write failed (disk full?)");
  return Ok{};
}

}  // namespace hlod
