// glTF 2.0 reader (.gltf and .glb) through tinygltf: walks the default scene applying node
// transforms in double precision; every triangle primitive becomes one Mesh with its base colour
// and base-colour texture, and every node instance with a mesh one object (Model::objectRuns):
// instances are flattened, each a copy. Accessor bounds are checked here as tinygltf does not
// check them all.
//
// Hostile files: tinygltf parses JSON recursively, so nesting depth is bounded before it parses;
// its file access goes through callbacks that read only inside the model's folder (no "~" or
// $VAR expansion, no fall-back to the current directory); the scene walk keeps its own stack and
// bounds what instancing expands to (kMaxGltfNodeInstances, kMaxGltfSceneElements).
//
// This is the one translation unit that compiles the tinygltf and stb implementations.
#define TINYGLTF_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <tiny_gltf.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <optional>

#include "hlod/JsonDepth.h"
#include "hlod/import/Import.h"
#include "hlod/import/InsideFolder.h"
#include "import/ImportUtil.h"

namespace hlod::import {
namespace {

// Arrays and objects nested deeper than this are refused before tinygltf parses them (it
// recurses per level and overflowed the stack at 20,000). glTF itself nests about 6 deep.
constexpr std::size_t kMaxGltfJsonDepth = 128;

// The JSON chunk of a GLB (header, then chunk 0 of type JSON); null when the header is not one,
// which tinygltf then reports.
const char* glbJson(const std::string& bytes, std::size_t& size) {
  if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0 ||
      std::memcmp(bytes.data() + 16, "JSON", 4) != 0)
    return nullptr;
  const auto length = loadScalar<std::uint32_t>(bytes.data() + 12, false);
  if (length > bytes.size() - 20) return nullptr;
  size = length;
  return bytes.data() + 20;
}

// tinygltf's file access, confined to the model's folder. tinygltf looks a URI up as
// JoinPath(baseDir, uri), then as "./uri" in the current directory: only the first is answered,
// and only when insideFolder accepts the URI. Refusals are kept to be reported by name.
struct ConfinedFiles {
  std::filesystem::path folder;  // the folder files may come from, as the user named it
  std::string
      baseDir;  // where URIs are relative to, canonical, given to tinygltf (no '/' at the end)
  std::string below;  // baseDir relative to folder, '/'-terminated ("" when they are one)
  std::vector<std::string> refused;

  // The file a path from tinygltf names, or empty when it is not to be touched.
  std::filesystem::path resolve(const std::string& joined) {
    const std::string prefix = baseDir + "/";
    if (joined.compare(0, prefix.size(), prefix) != 0) return {};  // the current-directory try
    const std::string reference = below + joined.substr(prefix.size());
    auto inside = insideFolder(folder, reference);
    if (inside) return *inside;
    if (std::find(refused.begin(), refused.end(), inside.message()) == refused.end())
      refused.push_back(inside.message());
    return {};
  }

  static ConfinedFiles& of(void* user) { return *static_cast<ConfinedFiles*>(user); }
  static std::string expand(const std::string& path, void*) { return path; }
  static bool exists(const std::string& path, void* user) {
    const std::filesystem::path p = of(user).resolve(path);
    std::error_code ec;
    return !p.empty() && std::filesystem::is_regular_file(p, ec);
  }
  static bool read(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                   void* user) {
    const std::filesystem::path p = of(user).resolve(path);
    if (p.empty()) {
      if (err) *err = "not inside the model's folder";
      return false;
    }
    auto bytes = readWholeFile(p);
    if (!bytes) {
      if (err) *err = bytes.message();
      return false;
    }
    out->assign(bytes->begin(), bytes->end());
    return true;
  }
  static bool write(std::string* err, const std::string&, const std::vector<unsigned char>&,
                    void*) {
    if (err) *err = "hlodr never writes glTF files";
    return false;
  }
};

// A checked view of an accessor's elements.
struct AccessorView {
  const unsigned char* data = nullptr;  // null: all zeros (accessor without buffer view)
  std::size_t stride = 0;
  std::size_t count = 0;
  int components = 0;
  int componentType = 0;
  bool normalized = false;

  double component(std::size_t i, int c) const {
    if (!data) return 0.0;
    const unsigned char* p = data + i * stride;
    switch (componentType) {
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        double v = static_cast<std::int8_t>(p[c]);
        return normalized ? std::max(v / 127.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
        double v = p[c];
        return normalized ? v / 255.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        double v = loadScalar<std::int16_t>(reinterpret_cast<const char*>(p) + 2 * c, false);
        return normalized ? std::max(v / 32767.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        double v = loadScalar<std::uint16_t>(reinterpret_cast<const char*>(p) + 2 * c, false);
        return normalized ? v / 65535.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        return loadScalar<std::uint32_t>(reinterpret_cast<const char*>(p) + 4 * c, false);
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return loadScalar<float>(reinterpret_cast<const char*>(p) + 4 * c, false);
      case TINYGLTF_COMPONENT_TYPE_DOUBLE:
        return loadScalar<double>(reinterpret_cast<const char*>(p) + 8 * c, false);
      default:
        return 0.0;
    }
  }
};

class GltfWalker {
 public:
  GltfWalker(const std::filesystem::path& path, const tinygltf::Model& gltf,
             bool oneSidedFromMaterial)
      : path_(path),
        oneSidedFromMaterial_(oneSidedFromMaterial),
        gltf_(gltf),
        images_(gltf.images.size()),
        imageDone_(gltf.images.size()),
        onPath_(gltf.nodes.size()) {}

  Result<Model> run() {
    int sceneIndex = gltf_.defaultScene >= 0 ? gltf_.defaultScene : 0;
    if (gltf_.scenes.empty()) {
      // No scene: show every mesh once, untransformed, rather than nothing.
      for (std::size_t m = 0; m < gltf_.meshes.size(); ++m)
        if (auto s = instance(static_cast<int>(m), glm::dmat4(1.0)); !s.ok()) return s.error();
    } else {
      if (sceneIndex >= static_cast<int>(gltf_.scenes.size()))
        return fileError(path_, "default scene " + std::to_string(sceneIndex) + " does not exist");
      for (int node : gltf_.scenes[static_cast<std::size_t>(sceneIndex)].nodes)
        if (auto s = walk(node); !s.ok()) return s.error();
    }
    return std::move(model_);
  }

 private:
  static glm::dmat4 localTransform(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) return glm::make_mat4(n.matrix.data());  // column-major, as glTF
    glm::dmat4 m(1.0);
    if (n.translation.size() == 3)
      m = glm::translate(m, glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
    if (n.rotation.size() == 4)
      m *= glm::mat4_cast(glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]));
    if (n.scale.size() == 3) m = glm::scale(m, glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
    return m;
  }

  // Depth-first, parents before children as the file lists them, on an explicit stack: a chain
  // of 20,000 nodes overflowed the call stack. The glTF spec forbids cycles and shared
  // children, which a forged file has anyway: a cycle is refused, and sharing is bounded by
  // the count of node instances (40 nodes that each list the next one twice expand to 2^40).
  Status walk(int rootIndex) {
    struct Frame {
      int node;
      glm::dmat4 world;
      std::size_t nextChild = 0;
    };
    std::vector<Frame> stack;
    auto enter = [&](int nodeIndex, const glm::dmat4& parent) -> Status {
      if (nodeIndex < 0 || nodeIndex >= static_cast<int>(gltf_.nodes.size()))
        return fileError(path_, "node index " + std::to_string(nodeIndex) + " out of range");
      const auto n = static_cast<std::size_t>(nodeIndex);
      if (onPath_[n])
        return fileError(path_, "node hierarchy has a cycle at node " + std::to_string(nodeIndex));
      if (++nodeInstances_ > kMaxGltfNodeInstances)
        return fileError(path_, "the scene expands to more than " +
                                    std::to_string(kMaxGltfNodeInstances) +
                                    " node instances (nodes listed as children of several "
                                    "parents are repeated under each)");
      onPath_[n] = true;
      const tinygltf::Node& node = gltf_.nodes[n];
      stack.push_back({nodeIndex, parent * localTransform(node)});
      if (node.mesh >= 0) return instance(node.mesh, stack.back().world);
      return Ok{};
    };
    if (auto s = enter(rootIndex, glm::dmat4(1.0)); !s.ok()) return s;
    while (!stack.empty()) {
      Frame& top = stack.back();
      assert(top.node >= 0 && static_cast<std::size_t>(top.node) < gltf_.nodes.size());  // enter()
      const auto& children = gltf_.nodes[static_cast<std::size_t>(top.node)].children;
      if (top.nextChild < children.size()) {
        const int child = children[top.nextChild++];
        const glm::dmat4 world = top.world;  // enter() may move the stack
        if (auto s = enter(child, world); !s.ok()) return s;
      } else {
        onPath_[static_cast<std::size_t>(top.node)] = false;
        stack.pop_back();
      }
    }
    return Ok{};
  }

  // The vertices and triangles a mesh's triangle primitives claim, from the accessor counts
  // alone (the accessors are checked when the mesh is read).
  std::pair<std::uint64_t, std::uint64_t> claimedSize(int meshIndex) const {
    std::uint64_t vertices = 0, triangles = 0;
    if (meshIndex < 0 || meshIndex >= static_cast<int>(gltf_.meshes.size())) return {0, 0};
    auto count = [&](int accessorIndex) -> std::uint64_t {
      if (accessorIndex < 0 || accessorIndex >= static_cast<int>(gltf_.accessors.size())) return 0;
      return gltf_.accessors[static_cast<std::size_t>(accessorIndex)].count;
    };
    for (const auto& prim : gltf_.meshes[static_cast<std::size_t>(meshIndex)].primitives) {
      const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
      auto pos = prim.attributes.find("POSITION");
      const std::uint64_t n = pos == prim.attributes.end() ? 0 : count(pos->second);
      const std::uint64_t corners = prim.indices >= 0 ? count(prim.indices) : n;
      if (mode == TINYGLTF_MODE_TRIANGLES)
        triangles += corners / 3;
      else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN)
        triangles += corners > 2 ? corners - 2 : 0;
      else
        continue;
      vertices += n;
    }
    return {vertices, triangles};
  }

  // One instance of a mesh: bounded before anything is allocated for it.
  Status instance(int meshIndex, const glm::dmat4& world) {
    const auto [vertices, triangles] = claimedSize(meshIndex);
    instancedVertices_ += vertices;
    instancedTriangles_ += triangles;
    if (instancedVertices_ > kMaxGltfSceneElements || instancedTriangles_ > kMaxGltfSceneElements)
      return fileError(path_, "the scene's mesh instances hold more than " +
                                  std::to_string(kMaxGltfSceneElements) +
                                  " vertices or triangles in all (at mesh " +
                                  std::to_string(meshIndex) + ")");
    // The instance is one object: its primitives' meshes, however many.
    const std::size_t firstMesh = model_.meshes.size();
    if (auto s = addMesh(meshIndex, world); !s.ok()) return s;
    for (std::size_t m = firstMesh; m < model_.meshes.size(); ++m)
      model_.objectRuns.push_back(
          {objects_, std::uint32_t(m), 0, std::uint32_t(model_.meshes[m].triangleCount())});
    if (model_.meshes.size() > firstMesh) ++objects_;
    return Ok{};
  }

  Result<AccessorView> accessor(int index, const std::string& what) {
    if (index < 0 || index >= static_cast<int>(gltf_.accessors.size()))
      return fileError(path_, what + ": accessor " + std::to_string(index) + " out of range");
    const tinygltf::Accessor& a = gltf_.accessors[static_cast<std::size_t>(index)];
    if (a.sparse.isSparse) return fileError(path_, what + ": sparse accessors are not supported");
    AccessorView v;
    v.count = a.count;
    v.componentType = a.componentType;
    v.normalized = a.normalized;
    v.components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    const int componentSize =
        tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
    if (v.components <= 0 || componentSize <= 0)
      return fileError(path_, what + ": bad accessor type");
    const std::size_t elementSize = static_cast<std::size_t>(v.components) * componentSize;
    if (a.bufferView < 0) {
      // All zeros by the spec: no bytes of the file back the count, so bound it here.
      if (v.count > kMaxGltfSceneElements)
        return fileError(path_, what + ": accessor without a buffer view claims " +
                                    std::to_string(v.count) + " elements (at most " +
                                    std::to_string(kMaxGltfSceneElements) + ")");
      return v;
    }
    if (a.bufferView >= static_cast<int>(gltf_.bufferViews.size()))
      return fileError(path_, what + ": buffer view out of range");
    const tinygltf::BufferView& bv = gltf_.bufferViews[static_cast<std::size_t>(a.bufferView)];
    if (bv.buffer < 0 || bv.buffer >= static_cast<int>(gltf_.buffers.size()))
      return fileError(path_, what + ": buffer out of range");
    const auto& buffer = gltf_.buffers[static_cast<std::size_t>(bv.buffer)].data;
    v.stride = bv.byteStride ? bv.byteStride : elementSize;
    if (v.stride < elementSize)
      return fileError(path_, what + ": byte stride smaller than element");
    // Both the view inside the buffer and the accessor inside the view must fit.
    if (bv.byteOffset > buffer.size() || bv.byteLength > buffer.size() - bv.byteOffset)
      return fileError(path_, what + ": buffer view exceeds its buffer (truncated file?)");
    if (v.count > 0) {
      if (a.byteOffset > bv.byteLength ||
          (v.count - 1) > (bv.byteLength - a.byteOffset) / v.stride ||
          a.byteOffset + (v.count - 1) * v.stride + elementSize > bv.byteLength)
        return fileError(path_, what + ": accessor exceeds its buffer view");
    }
    v.data = buffer.data() + bv.byteOffset + a.byteOffset;
    return v;
  }

  std::shared_ptr<const Image> image(int textureIndex) {
    if (textureIndex < 0 || textureIndex >= static_cast<int>(gltf_.textures.size())) return {};
    const int source = gltf_.textures[static_cast<std::size_t>(textureIndex)].source;
    if (source < 0 || source >= static_cast<int>(gltf_.images.size())) return {};
    const auto s = static_cast<std::size_t>(source);
    if (imageDone_[s]) return images_[s];
    imageDone_[s] = true;
    const tinygltf::Image& src = gltf_.images[s];
    const int c = src.component;
    const int bytesPerChannel = src.bits == 16 ? 2 : 1;
    const std::size_t pixels = static_cast<std::size_t>(std::max(src.width, 0)) *
                               static_cast<std::size_t>(std::max(src.height, 0));
    if (pixels == 0 || c < 1 || c > 4 || (src.bits != 8 && src.bits != 16) ||
        src.image.size() < pixels * c * bytesPerChannel) {
      warn(path_, "image " + std::to_string(source) + " not decoded; drawn untextured");
      return {};
    }
    auto img = std::make_shared<Image>();
    img->width = src.width;
    img->height = src.height;
    img->pixels.resize(pixels * 4);
    for (std::size_t i = 0; i < pixels; ++i) {
      std::uint8_t ch[4];
      for (int k = 0; k < c; ++k) {
        // 16-bit channels are little-endian in stb's output: keep the high byte.
        const std::size_t at = (i * c + k) * bytesPerChannel + (bytesPerChannel - 1);
        ch[k] = src.image[at];
      }
      std::uint8_t* d = &img->pixels[i * 4];
      if (c <= 2) {
        d[0] = d[1] = d[2] = ch[0];
        d[3] = c == 2 ? ch[1] : 255;
      } else {
        d[0] = ch[0];
        d[1] = ch[1];
        d[2] = ch[2];
        d[3] = c == 4 ? ch[3] : 255;
      }
    }
    images_[s] = img;
    return img;
  }

  Status addMesh(int meshIndex, const glm::dmat4& world) {
    if (meshIndex < 0 || meshIndex >= static_cast<int>(gltf_.meshes.size()))
      return fileError(path_, "mesh index " + std::to_string(meshIndex) + " out of range");
    const tinygltf::Mesh& gm = gltf_.meshes[static_cast<std::size_t>(meshIndex)];
    const glm::dmat3 linear(world);
    const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(linear));
    const bool mirrored = glm::determinant(linear) < 0.0;
    for (std::size_t pi = 0; pi < gm.primitives.size(); ++pi) {
      const tinygltf::Primitive& prim = gm.primitives[pi];
      const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
      if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
          mode != TINYGLTF_MODE_TRIANGLE_FAN)
        continue;  // points and lines have no surface
      const std::string what = "mesh " + std::to_string(meshIndex) + " ('" + gm.name +
                               "') primitive " + std::to_string(pi);
      auto posIt = prim.attributes.find("POSITION");
      if (posIt == prim.attributes.end()) return fileError(path_, what + ": no POSITION");
      auto pos = accessor(posIt->second, what + " POSITION");
      if (!pos.ok()) return pos.error();
      if (pos->components < 3) return fileError(path_, what + ": POSITION is not a VEC3");
      Mesh mesh;
      mesh.name = gm.name.empty() ? "mesh" + std::to_string(meshIndex) : gm.name;
      if (gm.primitives.size() > 1) mesh.name += "#" + std::to_string(pi);
      const std::size_t n = pos->count;
      mesh.positions.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        glm::dvec4 p(pos->component(i, 0), pos->component(i, 1), pos->component(i, 2), 1.0);
        mesh.positions[i] = glm::dvec3(world * p);
      }
      if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
        auto nrm = accessor(it->second, what + " NORMAL");
        if (!nrm.ok()) return nrm.error();
        if (nrm->count != n || nrm->components < 3)
          return fileError(path_, what + ": NORMAL count or type differs from POSITION");
        mesh.normals.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
          glm::dvec3 v = normalMatrix * glm::dvec3(nrm->component(i, 0), nrm->component(i, 1),
                                                   nrm->component(i, 2));
          // Unit normals stay as written: dividing by a length within rounding of 1 would
          // change their last bits (a tileset read back would no longer be the store it was).
          const double len = glm::length(v);
          mesh.normals[i] = glm::vec3(len > 0.0 && std::abs(len - 1.0) > 1e-6 ? v / len : v);
        }
      }
      // Material: base colour factor and texture (with the texture's own coordinate set).
      int texCoordSet = 0;
      mesh.oneSided = oneSidedFromMaterial_;  // glTF's default material is single-sided
      if (prim.material >= 0 && prim.material < static_cast<int>(gltf_.materials.size())) {
        const tinygltf::Material& material =
            gltf_.materials[static_cast<std::size_t>(prim.material)];
        const auto& pbr = material.pbrMetallicRoughness;
        mesh.oneSided = oneSidedFromMaterial_ && !material.doubleSided;
        if (pbr.baseColorFactor.size() == 4)
          mesh.baseColor = glm::vec4(glm::dvec4(pbr.baseColorFactor[0], pbr.baseColorFactor[1],
                                                pbr.baseColorFactor[2], pbr.baseColorFactor[3]));
        if (pbr.baseColorTexture.index >= 0) {
          mesh.texture = image(pbr.baseColorTexture.index);
          texCoordSet = std::max(pbr.baseColorTexture.texCoord, 0);
        }
      }
      if (auto it = prim.attributes.find("TEXCOORD_" + std::to_string(texCoordSet));
          it != prim.attributes.end()) {
        auto uv = accessor(it->second, what + " TEXCOORD");
        if (!uv.ok()) return uv.error();
        if (uv->count != n || uv->components < 2)
          return fileError(path_, what + ": TEXCOORD count or type differs from POSITION");
        mesh.texCoords.resize(n);
        for (std::size_t i = 0; i < n; ++i)
          mesh.texCoords[i] = glm::vec2(static_cast<float>(uv->component(i, 0)),
                                        static_cast<float>(uv->component(i, 1)));
      } else if (mesh.texture) {
        mesh.texture.reset();  // a texture without coordinates cannot be mapped
      }
      // Indices (or 0..n-1), then strips and fans turned into triangle lists.
      std::vector<std::uint32_t> raw;
      if (prim.indices >= 0) {
        auto idx = accessor(prim.indices, what + " indices");
        if (!idx.ok()) return idx.error();
        if (idx->components != 1 || (idx->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                     idx->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                     idx->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
          return fileError(path_, what + ": indices must be unsigned byte, short or int scalars");
        raw.resize(idx->count);
        for (std::size_t i = 0; i < idx->count; ++i) {
          const double v = idx->component(i, 0);
          if (v >= static_cast<double>(n))
            return fileError(path_, what + ": face index " +
                                        std::to_string(static_cast<std::uint64_t>(v)) +
                                        " out of range (" + std::to_string(n) + " vertices)");
          raw[i] = static_cast<std::uint32_t>(v);
        }
      } else {
        if (n > 0xffffffffULL) return fileError(path_, what + ": too many vertices");
        raw.resize(n);
        for (std::size_t i = 0; i < n; ++i) raw[i] = static_cast<std::uint32_t>(i);
      }
      if (mode == TINYGLTF_MODE_TRIANGLES) {
        raw.resize(raw.size() / 3 * 3);
        mesh.indices = std::move(raw);
      } else {
        for (std::size_t i = 2; i < raw.size(); ++i) {
          if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
            mesh.indices.insert(mesh.indices.end(), {raw[0], raw[i - 1], raw[i]});
          } else if (i % 2 == 0) {
            mesh.indices.insert(mesh.indices.end(), {raw[i - 2], raw[i - 1], raw[i]});
          } else {
            mesh.indices.insert(mesh.indices.end(), {raw[i - 1], raw[i - 2], raw[i]});
          }
        }
      }
      if (mirrored)  // a mirroring transform flips the winding: restore counter-clockwise
        for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
          std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
      model_.meshes.push_back(std::move(mesh));
    }
    return Ok{};
  }

  const std::filesystem::path& path_;
  const bool oneSidedFromMaterial_;
  const tinygltf::Model& gltf_;
  std::vector<std::shared_ptr<const Image>> images_;
  std::vector<bool> imageDone_;
  std::vector<bool> onPath_;  // nodes on the walk's current path: a repeat is a cycle
  std::uint64_t nodeInstances_ = 0;
  std::uint64_t instancedVertices_ = 0;
  std::uint64_t instancedTriangles_ = 0;
  std::uint32_t objects_ = 0;  // node instances with triangles so far
  Model model_;
};

}  // namespace

namespace {

// CESIUM_RTC (a 3D Tiles 1.0 extension): positions are relative to this centre.
std::optional<glm::dvec3> cesiumRtcCenter(const tinygltf::Model& gltf) {
  const auto it = gltf.extensions.find("CESIUM_RTC");
  if (it == gltf.extensions.end() || !it->second.IsObject()) return std::nullopt;
  const tinygltf::Value& centre = it->second.Get("center");
  if (!centre.IsArray() || centre.ArrayLen() != 3) return std::nullopt;
  glm::dvec3 c(0.0);
  for (int k = 0; k < 3; ++k) {
    const tinygltf::Value& v = centre.Get(k);
    if (!v.IsNumber()) return std::nullopt;
    c[k] = v.GetNumberAsDouble();
  }
  return c;
}

// Parses glTF text or GLB bytes and walks its scene. `path` names it in messages; files it refers
// to are looked up relative to baseDir and read only from inside `folder`.
Result<GltfContent> readGltfFrom(const std::filesystem::path& path, std::string bytes, bool binary,
                                 const std::filesystem::path& folder,
                                 const std::filesystem::path& baseDir, bool oneSidedFromMaterial) {
  if (bytes.empty()) return fileError(path, "file is empty");
  if (bytes.size() > 0xffffffffu) return fileError(path, "file larger than 4 GB");
  std::size_t jsonSize = bytes.size();
  const char* json = binary ? glbJson(bytes, jsonSize) : bytes.data();
  if (json && jsonDepth(json, jsonSize, kMaxGltfJsonDepth) > kMaxGltfJsonDepth)
    return fileError(path,
                     "JSON nested deeper than " + std::to_string(kMaxGltfJsonDepth) + " levels");

  ConfinedFiles files;
  files.folder = folder.empty() ? std::filesystem::path(".") : folder;
  std::error_code ec;
  files.baseDir =
      std::filesystem::canonical(baseDir.empty() ? std::filesystem::path(".") : baseDir, ec)
          .string();
  if (ec) return fileError(path, "cannot resolve the file's folder");
  const std::filesystem::path top = std::filesystem::canonical(files.folder, ec);
  if (ec) return fileError(path, "cannot resolve the model's folder");
  if (files.baseDir.size() > 1 && files.baseDir.back() == '/') files.baseDir.pop_back();
  const std::filesystem::path below = std::filesystem::path(files.baseDir).lexically_relative(top);
  if (!below.empty() && below != ".") files.below = below.generic_string() + "/";
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&ConfinedFiles::exists, &ConfinedFiles::expand, &ConfinedFiles::read,
                         &ConfinedFiles::write, &files});
  tinygltf::Model gltf;
  std::string err, warning;
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const auto size = static_cast<unsigned int>(bytes.size());
  const bool ok =
      binary ? loader.LoadBinaryFromMemory(&gltf, &err, &warning, data, size, files.baseDir)
             : loader.LoadASCIIFromString(&gltf, &err, &warning, bytes.data(), size, files.baseDir);
  bytes = std::string();  // tinygltf holds its own copies now
  auto trim = [](std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    for (char& c : s)
      if (c == '\n') c = ';';
    return s;
  };
  // A refused reference explains a failure better than tinygltf's "file not found".
  if (!ok)
    return fileError(path, "cannot load glTF: " + (!files.refused.empty() ? files.refused.front()
                                                   : err.empty() ? std::string("unknown error")
                                                                 : trim(err)));
  for (const auto& refused : files.refused) warn(path, refused + "; not read");
  if (!warning.empty()) warn(path, trim(warning));
  auto model = GltfWalker(path, gltf, oneSidedFromMaterial).run();
  if (!model) return model.error();
  return GltfContent{std::move(*model), cesiumRtcCenter(gltf)};
}

}  // namespace

Result<Model> readGltf(const std::filesystem::path& path, bool binary) {
  auto bytes = readWholeFile(path);
  if (!bytes) return bytes.error();
  const std::filesystem::path folder =
      path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  auto scene = readGltfFrom(path, std::move(*bytes), binary, folder, folder, false);
  if (!scene) return scene.error();
  return std::move(scene->model);
}

Result<GltfContent> readGltfBytes(const GltfBytes& in) {
  return readGltfFrom(in.name, std::string(in.bytes), in.binary, in.folder, in.baseDir,
                      in.oneSidedFromMaterial);
}

}  // namespace hlod::import
