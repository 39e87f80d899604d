// HLOD generation over the object hierarchy, Manocha sec. 2.2.1: "The HLODs are computed in a
// bottom-up manner. The HLODs of the leaf nodes are the same as static LODs, while the HLODs of
// intermediate nodes are computed by combining the LODs of the nodes with the HLODs of the node's
// children [...] by keeping only the LODs of the current node and its children in main memory,
// HLOD generation is accomplished within a small memory footprint." The paper simplifies with
// GAPS (Erikson and Manocha 1999), which merges disjoint objects; here vertex clustering does
// that within Simplifier::simplifyUnion (HlodBuilder.h, addObjectHierarchy).
#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <map>
#include <thread>
#include <tuple>
#include <unordered_map>

#include "builder/BlockBorders.h"
#include "builder/CellColours.h"
#include "builder/Preprocess.h"
#include "builder/TextureCrop.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/parry/Splats.h"

namespace hlod {

namespace {

// An HLOD corner keeps its input normal within 45 degrees of its face (CellColours.h).
constexpr float kSmoothCos = 0.7071f;

struct Material {
  const Image* texture;
  float r, g, b, a;
  bool operator<(const Material& o) const {
    return std::tie(texture, r, g, b, a) < std::tie(o.texture, o.r, o.g, o.b, o.a);
  }
};

Material materialOf(const Mesh& m) {
  return {m.texture.get(), m.baseColor.r, m.baseColor.g, m.baseColor.b, m.baseColor.a};
}

// The mean of an image's pixels (white for none): a textured mesh's colour in a palette.
glm::vec4 meanColour(const Image* image) {
  if (!image || image->empty() ||
      image->pixels.size() != std::size_t(image->width) * image->height * 4)
    return glm::vec4(1.0f);
  glm::dvec4 sum(0.0);
  for (std::size_t i = 0; i + 3 < image->pixels.size(); i += 4)
    sum += glm::dvec4(image->pixels[i], image->pixels[i + 1], image->pixels[i + 2],
                      image->pixels[i + 3]);
  return glm::vec4(sum / (255.0 * double(image->pixels.size() / 4)));
}

// A palette texture of the colours, one texel each, and the coordinates of each one's centre.
std::shared_ptr<const Image> paletteImage(const std::vector<glm::vec4>& colours,
                                          std::vector<glm::vec2>& centres) {
  const int side = std::max(1, int(std::ceil(std::sqrt(double(colours.size())))));
  auto image = std::make_shared<Image>();
  image->width = image->height = side;
  image->pixels.assign(std::size_t(side) * side * 4, 255);
  for (std::size_t k = 0; k < colours.size(); ++k) {
    for (int ch = 0; ch < 4; ++ch)
      image->pixels[4 * k + std::size_t(ch)] =
          std::uint8_t(std::lround(std::clamp(colours[k][ch], 0.0f, 1.0f) * 255.0f));
    centres.push_back((glm::vec2(float(int(k) % side), float(int(k) / side)) + 0.5f) / float(side));
  }
  return image;
}

// A leaf: the triangles of its redefined object's pieces, with the vertices they use. One
// material keeps it; several become flat colours of a palette (a textured mesh at the mean colour
// of its texture).
Mesh leafMesh(const Model& model, const RedefinedObject& object,
              const std::vector<std::vector<ObjectRun>>& byObject) {
  // The triangles per mesh, in the pieces' order.
  std::map<std::uint32_t, std::vector<std::uint32_t>> perMesh;
  for (const ObjectPiece& piece : object.pieces) {
    const auto triangles = objectTriangles(byObject[piece.object]);
    if (piece.triangles.empty())
      for (const auto& [mesh, t] : triangles) perMesh[mesh].push_back(t);
    else
      for (std::uint32_t k : piece.triangles)
        perMesh[triangles[k].first].push_back(triangles[k].second);
  }
  std::map<Material, std::size_t> materials;
  bool oneSided = true, texCoords = true;
  for (const auto& [m, tris] : perMesh) {
    const Mesh& mesh = model.meshes[m];
    materials.try_emplace(materialOf(mesh), materials.size());
    oneSided = oneSided && mesh.oneSided;
    texCoords = texCoords && mesh.texCoords.size() == mesh.positions.size();
  }
  const bool palette = materials.size() > 1;
  Mesh out;
  out.oneSided = oneSided;
  std::vector<glm::vec2> texel;  // per material (palette)
  if (palette) {
    std::vector<glm::vec4> colours(materials.size());
    for (const auto& [mat, k] : materials)
      colours[k] = glm::vec4(mat.r, mat.g, mat.b, mat.a) * meanColour(mat.texture);
    out.texture = paletteImage(colours, texel);
    out.baseColor = glm::vec4(1.0f);
  } else {
    const Mesh& first = model.meshes[perMesh.begin()->first];
    out.baseColor = first.baseColor;
    out.texture = texCoords ? first.texture : nullptr;
  }
  const std::shared_ptr<const Image> texture = palette ? nullptr : out.texture;
  for (const auto& [m, tris] : perMesh) {
    const Mesh& mesh = model.meshes[m];
    const std::size_t material = materials.at(materialOf(mesh));
    std::vector<std::uint32_t> local;
    std::unordered_map<std::uint32_t, std::uint32_t> remap;
    const auto base = std::uint32_t(out.positions.size());
    for (std::uint32_t t : tris)
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t v = mesh.indices[3 * std::size_t(t) + std::size_t(c)];
        auto [it, fresh] = remap.try_emplace(v, std::uint32_t(remap.size()));
        if (fresh) {
          out.positions.push_back(mesh.positions[v]);
          if (palette)
            out.texCoords.push_back(texel[material]);
          else if (out.texture)
            out.texCoords.push_back(mesh.texCoords[v]);
        }
        local.push_back(it->second);
      }
    // Normals: the mesh's own, or computed for this part (a mesh without them).
    if (mesh.normals.size() == mesh.positions.size()) {
      out.normals.resize(out.positions.size());
      for (const auto& [v, k] : remap) out.normals[base + k] = mesh.normals[v];
    } else {
      const std::vector<glm::dvec3> part(out.positions.begin() + base, out.positions.end());
      const std::vector<glm::vec3> n = computeVertexNormals(part, local);
      out.normals.insert(out.normals.end(), n.begin(), n.end());
    }
    for (std::uint32_t i : local) out.indices.push_back(base + i);
  }
  // A texture of its own, cropped to what the leaf uses (an atlas is not stored whole per leaf).
  if (texture) out.texture = prepareNodeTexture(*texture, out.texCoords, 1.0);
  return out;
}

// A node's payload, ready to append, and its record's measures.
StoredPayload storeNode(const Mesh& mesh, NodeInfo& info, double cTex) {
  describeNode(info, mesh, cTex);
  LocalMesh local = localAround(mesh, info.centre);
  local.splats = makeSplats(local);
  info.splatCount = std::uint32_t(local.splats.size());
  return storePayload(local);
}

}  // namespace

ObjectHierarchyOptions objectHierarchyOptions(const BuildOptions& options) {
  ObjectHierarchyOptions o;
  o.fanOut = options.levelFactor;
  o.maxTriangles = std::uint64_t(options.levelFactor) * options.minLeafTri;
  return o;
}

Status HlodBuilder::addObjectHierarchy(
    const Model& model, const ObjectHierarchy& hierarchy,
    const std::function<void(std::size_t, std::size_t)>& progress) {
  const auto& tree = hierarchy.nodes;
  if (tree.empty()) return Ok{};
  if (!skeleton_.nodes.empty())
    return makeError("the object hierarchy must be the store's only block");
  if (tree.size() >= kNoNode) return makeError("too many nodes");
  const std::vector<std::vector<ObjectRun>> byObject = objectRunsByObject(model);
  std::vector<NodeInfo> nodes(tree.size());
  for (std::size_t i = 0; i < tree.size(); ++i) {
    NodeInfo& n = nodes[i];
    n.parent = tree[i].parent == 0xffffffffu ? kNoNode : tree[i].parent;
    n.firstChild = tree[i].firstChild;
    n.childCount = tree[i].childCount;
    n.level = tree[i].level;
    n.block = 0;
  }
  // A leaf's payload from the model; an inner node's from its children's (read back before).
  const auto prepare = [&](std::size_t i, std::vector<LocalMesh> children) {
    NodeInfo& info = nodes[i];
    if (info.childCount == 0) {
      const Mesh mesh = leafMesh(model, hierarchy.objects[tree[i].object], byObject);
      info.bounds = mesh.bounds();
      info.centre = info.bounds.centre();
      info.geometricError = 0.0;
      return storeNode(mesh, info, options_.cTex);
    }
    std::uint64_t childTriangles = 0;
    for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c) {
      info.bounds.extend(nodes[c].bounds);
      info.geometricError = std::max(info.geometricError, nodes[c].geometricError);
      childTriangles += nodes[c].numTri;
    }
    const ColouredMesh coloured = mergeCellChildren(children);
    children.clear();
    Mesh merged = weldVertices(coloured.mesh);
    dropRepeatedTriangles(merged);
    const std::size_t target = std::clamp<std::size_t>(
        childTriangles / std::size_t(options_.levelFactor), options_.desiredTri,
        std::max<std::size_t>(1, merged.triangleCount()));
    const double factor = double(merged.triangleCount()) / double(target);
    SimplifiedMesh simplified = simplifier_->simplifyUnion(
        merged, target, {}, errorLimit(surfaceArea(merged), merged.triangleCount(), factor));
    info.geometricError += simplified.geometricError;
    // (A simplification that kept nothing leaves the children's triangles as they are.)
    const Mesh mesh = flatColoured(simplified.mesh.triangleCount() > 0 ? simplified.mesh : merged,
                                   coloured.colours, kSmoothCos);
    info.bounds.extend(mesh.bounds());
    info.centre = info.bounds.centre();
    return storeNode(mesh, info, options_.cTex);
  };
  // Level by level from the deepest (children before parents), a window of nodes at a time:
  // their children read back in order, the nodes prepared on every thread, then appended in
  // order, so that the store is the same for any thread count and memory holds the window.
  const unsigned threads =
      options_.threads ? options_.threads : std::max(1u, std::thread::hardware_concurrency());
  const std::size_t window = 2 * std::size_t(threads);
  std::uint32_t depth = 0;
  for (const auto& n : tree) depth = std::max(depth, n.level);
  std::vector<std::vector<std::size_t>> byLevel(std::size_t(depth) + 1);
  for (std::size_t i = 0; i < tree.size(); ++i) byLevel[tree[i].level].push_back(i);
  std::size_t done = 0;
  for (std::size_t level = byLevel.size(); level-- > 0;) {
    const std::vector<std::size_t>& at = byLevel[level];
    // The level below is appended whole: readable once flushed (NodeStoreWriter::readBack).
    if (auto f = writer_->flush(); !f) return f.error();
    for (std::size_t first = 0; first < at.size(); first += window) {
      const std::size_t count = std::min(window, at.size() - first);
      std::vector<std::vector<LocalMesh>> children(count);
      for (std::size_t k = 0; k < count; ++k) {
        const NodeInfo& info = nodes[at[first + k]];
        for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c) {
          auto child = writer_->readBack(nodes[c]);
          if (!child) return child.error();
          children[k].push_back(std::move(*child));
        }
      }
      std::vector<StoredPayload> payloads(count);
      std::atomic<std::size_t> next{0};
      std::vector<std::string> failed(count);  // an exception (bad_alloc) stops the build
      const auto work = [&] {
        for (std::size_t k; (k = next++) < count;) try {
            payloads[k] = prepare(at[first + k], std::move(children[k]));
          } catch (const std::exception& e) {
            failed[k] = std::string("object hierarchy node ") + std::to_string(at[first + k]) +
                        ": " + e.what();
          }
      };
      std::vector<std::thread> workers;
      for (unsigned t = 1; t < std::min<std::size_t>(threads, count); ++t)
        workers.emplace_back(work);
      work();
      for (std::thread& w : workers) w.join();
      for (const std::string& f : failed)
        if (!f.empty()) return makeError(f);
      for (std::size_t k = 0; k < count; ++k) {
        NodeInfo& info = nodes[at[first + k]];
        if (info.childCount == 0) inputTriangles_ += info.numTri;
        if (auto s = writer_->appendStored(payloads[k], info); !s) return s;
        payloads[k] = {};
        if (progress) progress(++done, tree.size());
      }
    }
  }
  skeleton_.nodes = std::move(nodes);
  skeleton_.roots = {0};
  anchors_.push_back(std::nullopt);
  sides_.emplace_back();
  seams_.emplace_back();
  blockCount_ = 1;
  return Ok{};
}

}  // namespace hlod
