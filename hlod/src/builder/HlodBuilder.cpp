// Lakhia et al., "Interactive rendering of large city models", sec. III-A (model preparation)
// and III-B (per-node pre-processing).
#include "hlod/builder/HlodBuilder.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <unordered_map>

#include "builder/BlockBorders.h"
#include "builder/CellNodes.h"
#include "builder/FacadePartition.h"
#include "builder/MaterialKey.h"
#include "builder/Preprocess.h"
#include "builder/SimplifierImpl.h"
#include "builder/SlabPartition.h"
#include "builder/TextureCrop.h"
#include "hlod/city/City.h"
#include "hlod/parry/Splats.h"

namespace hlod {

namespace {

double rootSimplification(const Mesh& welded, const BuildOptions& options) {
  return double(welded.triangleCount()) / std::max<std::uint32_t>(1, options.desiredTri);
}

}  // namespace

std::vector<BlockNode> buildBlockHierarchy(const Mesh& block, const BuildOptions& options,
                                           const Simplifier& simplifier,
                                           std::span<const glm::dvec3> seam,
                                           std::span<const CutPlane> blockSides) {
  assert(options.levelFactor >= 2 && options.minLeafTri >= 1);
  std::vector<BlockNode> nodes;
  Mesh welded = weldVertices(block);
  if (welded.triangleCount() == 0) return nodes;
  const int levelFactor = options.levelFactor;
  BlockBorders borders = blockBorders(welded, seam);
  const double blockArea = surfaceArea(welded);
  const std::size_t blockTriangles = welded.triangleCount();
  const bool byFacade = std::string_view(simplifier.name()) == "parry";
  // Pieces waiting to become nodes: their original triangles, and their vertices' block vertices.
  std::vector<Mesh> pieces;
  std::vector<std::vector<std::uint32_t>> origins;
  nodes.emplace_back();
  nodes[0].info.parent = kNoNode;
  nodes[0].simplification = rootSimplification(welded, options);  // s_hlod0
  origins.emplace_back(welded.positions.size());
  for (std::uint32_t v = 0; v < origins[0].size(); ++v) origins[0][v] = v;
  pieces.push_back(std::move(welded));

  for (std::size_t i = 0; i < nodes.size(); ++i) {
    Mesh piece = std::move(pieces[i]);
    std::vector<std::uint32_t> origin = std::move(origins[i]);
    pieces[i] = Mesh{};
    origins[i] = {};
    const double s = nodes[i].simplification;
    const Aabb box = piece.bounds();
    nodes[i].info.bounds = box;
    nodes[i].info.centre = box.centre();
    // Children: levelFactor slabs of the piece's original triangles, s_{d+1} = s_d / levelFactor.
    // (The nodes are visited breadth-first: nodes[] grows level by level.)
    SlabPartition slabs;
    bool inner = s > 1.0 && piece.triangleCount() >= std::size_t(levelFactor) * options.minLeafTri;
    // Parry's block tree (Fig. 3): the block's children are its facades.
    if (inner && i == 0 && byFacade) {
      slabs = partitionIntoFacades(piece, options.up.value_or(UpAxis::Z), options.minLeafTri);
      if (slabs.triangles.size() < 2) slabs = SlabPartition{};
    }
    if (inner && slabs.triangles.empty()) {
      slabs = divideIntoSlabs(piece, levelFactor, options.minLeafTri);
      inner = slabs.triangles.size() > 1;  // one: the centroids all lie on one plane
    }
    if (!inner) {
      nodes[i].mesh = std::move(piece);  // a leaf: the original triangles
      nodes[i].simplification = 1.0;
      nodes[i].info.geometricError = 0.0;
      continue;
    }
    const auto target =
        std::max<std::size_t>(1, std::size_t(std::llround(double(piece.triangleCount()) / s)));
    std::vector<std::uint8_t> locked = lockBorder(piece, origin, borders);
    markOutline(piece, origin, borders, blockSides, locked);
    SimplifiedMesh simplified =
        simplifier.simplify(piece, target, locked, errorLimit(blockArea, blockTriangles, s));
    nodes[i].mesh = std::move(simplified.mesh);
    nodes[i].info.geometricError = simplified.geometricError;
    nodes[i].cutAxis = slabs.axis;
    nodes[i].cutPlanes = slabs.planes;
    nodes[i].info.firstChild = std::uint32_t(nodes.size());
    for (const std::vector<std::uint32_t>& triangles : slabs.triangles) {
      BlockNode n;
      n.info.parent = std::uint32_t(i);
      n.info.level = nodes[i].info.level + 1;
      n.simplification = s / double(levelFactor);
      nodes.push_back(std::move(n));
      std::vector<std::uint32_t> local;
      pieces.push_back(subMesh(piece, triangles, &local));
      for (std::uint32_t& v : local) v = origin[v];
      origins.push_back(std::move(local));
      ++nodes[i].info.childCount;
    }
  }
  // A parent is never more accurate than its children: make the error monotone, bottom up.
  for (std::size_t i = nodes.size(); i-- > 1;) {
    auto& parent = nodes[nodes[i].info.parent].info;
    parent.geometricError = std::max(parent.geometricError, nodes[i].info.geometricError);
  }
  return nodes;
}

namespace {

void appendMesh(Mesh& dst, const Mesh& src) {
  const auto base = std::uint32_t(dst.positions.size());
  const bool dstEmpty = dst.positions.empty();
  const bool n = (dstEmpty || dst.normals.size() == dst.positions.size()) &&
                 src.normals.size() == src.positions.size();
  const bool uv = (dstEmpty || dst.texCoords.size() == dst.positions.size()) &&
                  src.texCoords.size() == src.positions.size();
  if (!n) dst.normals.clear();
  if (!uv) dst.texCoords.clear();
  dst.positions.insert(dst.positions.end(), src.positions.begin(), src.positions.end());
  if (n) dst.normals.insert(dst.normals.end(), src.normals.begin(), src.normals.end());
  if (uv) dst.texCoords.insert(dst.texCoords.end(), src.texCoords.begin(), src.texCoords.end());
  for (std::uint32_t i : src.indices) dst.indices.push_back(base + i);
}

// The parts of one welded mesh as blocks, each with the positions it shares with the others.
void appendBlocks(const Mesh& mesh, const std::vector<std::vector<std::uint32_t>>& parts,
                  std::vector<Block>& blocks) {
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  constexpr std::uint32_t kShared = kNone - 1;
  std::unordered_map<glm::dvec3, std::uint32_t, PositionHash> owner;  // part, or kShared
  if (parts.size() > 1)
    for (std::uint32_t k = 0; k < parts.size(); ++k)
      for (std::uint32_t t : parts[k])
        for (int c = 0; c < 3; ++c) {
          auto [it, fresh] = owner.try_emplace(
              mesh.positions[mesh.indices[std::size_t(t) * 3 + c]] + glm::dvec3(0.0), k);
          if (!fresh && it->second != k) it->second = kShared;
        }
  for (std::size_t k = 0; k < parts.size(); ++k) {
    Block block;
    block.mesh = subMesh(mesh, parts[k]);
    if (parts.size() > 1) block.mesh.name = mesh.name + "#" + std::to_string(k);
    std::unordered_map<glm::dvec3, char, PositionHash> seen;
    for (const glm::dvec3& p : block.mesh.positions) {
      auto it = owner.find(p + glm::dvec3(0.0));
      if (it != owner.end() && it->second == kShared &&
          seen.try_emplace(p + glm::dvec3(0.0)).second)
        block.seam.push_back(p);
    }
    blocks.push_back(std::move(block));
  }
}

}  // namespace

std::vector<Block> cutIntoBlocks(const Model& model, std::size_t maxTriangles) {
  // One texture per node payload: group meshes by material first.
  std::map<MaterialKey, Mesh> groups;
  for (const Mesh& m : model.meshes) {
    if (m.triangleCount() == 0) continue;
    const MaterialKey key = materialKeyOf(m);
    auto [it, fresh] = groups.try_emplace(key);
    if (fresh) {
      it->second.name = m.name;
      it->second.baseColor = m.baseColor;
      it->second.texture = m.texture;
      it->second.oneSided = m.oneSided;
    }
    appendMesh(it->second, m);
  }
  std::vector<Block> blocks;
  for (auto& [key, group] : groups) {
    const Mesh mesh = weldVertices(group);
    group = Mesh{};
    std::vector<glm::dvec3> centroids(mesh.triangleCount());
    std::vector<std::uint32_t> all(mesh.triangleCount());
    for (std::uint32_t t = 0; t < all.size(); ++t) {
      all[t] = t;
      centroids[t] = centroid(mesh, t);
    }
    std::vector<std::vector<std::uint32_t>> parts;
    halveUntilSmall(centroids, std::move(all), std::max<std::size_t>(1, maxTriangles), 0, parts);
    appendBlocks(mesh, parts, blocks);
  }
  return blocks;
}

Result<std::unique_ptr<HlodBuilder>> HlodBuilder::create(const std::filesystem::path& dir,
                                                         const BuildOptions& options) {
  if (options.levelFactor < 2 || options.levelFactor > 64)
    return makeError("levelFactor must be an integer in [2, 64]");
  if (options.desiredTri < 1) return makeError("desiredTri must be at least 1");
  if (options.minLeafTri < 1) return makeError("minLeafTri must be at least 1");
  if (!(options.cTex >= 0.0 && options.cTex <= 1.0)) return makeError("c_tex must be in [0, 1]");
  auto simplifier = makeSimplifier(options.simplifier);
  if (!simplifier) return simplifier.error();
  auto writer = NodeStoreWriter::create(dir);
  if (!writer) return writer.error();
  std::unique_ptr<HlodBuilder> b(new HlodBuilder());
  b->options_ = options;
  b->simplifier_ = std::move(*simplifier);
  b->writer_ = std::move(*writer);
  b->skeleton_.params.levelFactor = options.levelFactor;
  b->skeleton_.params.desiredTri = options.desiredTri;
  b->skeleton_.params.cTex = options.cTex;
  b->skeleton_.params.simplifier = options.simplifier;
  if (options.up) b->skeleton_.up = *options.up;
  return b;
}

void HlodBuilder::setModelFrame(UpAxis up, const ModelCrs& crs) {
  skeleton_.up = options_.up.value_or(up);
  skeleton_.crs = crs;
}

Status HlodBuilder::addBlock(const Mesh& block, std::span<const glm::dvec3> seam,
                             std::span<const CutPlane> sides) {
  return commitBlock(prepareBlock(block, seam, sides));
}

PreparedBlock HlodBuilder::prepareBlock(const Mesh& block, std::span<const glm::dvec3> seam,
                                        std::span<const CutPlane> sides) const {
  PreparedBlock out;
  out.inputTriangles = block.triangleCount();
  out.sides.assign(sides.begin(), sides.end());
  out.seam.assign(seam.begin(), seam.end());
  std::vector<BlockNode> local = buildBlockHierarchy(block, options_, *simplifier_, seam, sides);
  std::vector<LocalMesh> meshes(local.size());
  // Texture groups: the nodes of one level drawn at one resolution (inner nodes at the level's
  // factor, leaves at full detail), in node order.
  std::map<std::pair<std::uint32_t, bool>, std::vector<std::size_t>> groups;
  for (std::size_t k = 0; k < local.size(); ++k) {
    BlockNode& n = local[k];
    NodeInfo info = n.info;
    describeNode(info, n.mesh, options_.cTex);
    LocalMesh& lm = meshes[k];
    lm = localAround(n.mesh, info.centre);  // the piece's centre, so that node centres nest
    lm.texture = nullptr;
    const Image* texture = n.mesh.texture.get();
    if (texture && !texture->empty() &&
        texture->pixels.size() == std::size_t(texture->width) * texture->height * 4 &&
        lm.texCoords.size() == lm.positions.size())
      groups[{info.level, info.childCount == 0}].push_back(k);
    n.mesh.positions = {};
    n.mesh.indices = {};
    out.nodes.push_back(info);
  }
  // A group whose crops overlap (an atlas whose every part each node uses) stores one texture,
  // their union, in its first node; the others share it. Otherwise each node keeps its crop:
  // either way a level's texture bytes stay within kSharedTextureOverlap of its texture's.
  out.textureOwner.assign(local.size(), kNoNode);
  for (const auto& [key, members] : groups) {
    const Image& texture = *local[members.front()].mesh.texture;
    const double factor = local[members.front()].simplification;
    TexelRect all{texture.width, texture.height, 0, 0};
    double sum = 0.0;
    for (std::size_t k : members) {
      const TexelRect r = usedTexels(texture, meshes[k].texCoords);
      sum += r.area();
      all = {std::min(all.x0, r.x0), std::min(all.y0, r.y0), std::max(all.x1, r.x1),
             std::max(all.y1, r.y1)};
    }
    if (members.size() < 2 || sum <= kSharedTextureOverlap * all.area()) {
      for (std::size_t k : members)
        meshes[k].texture = prepareNodeTexture(texture, meshes[k].texCoords, factor);
      continue;
    }
    meshes[members.front()].texture = cropImage(texture, all, factor);
    for (std::size_t k : members) {
      remapToRect(texture, all, meshes[k].texCoords);
      if (k == members.front()) continue;
      meshes[k].texture = meshes[members.front()].texture;
      out.textureOwner[k] = std::uint32_t(members.front());
    }
  }
  for (std::size_t k = 0; k < local.size(); ++k) {
    local[k].mesh = Mesh{};
    // After the texture crops: the splats take their texture coordinates from the vertices.
    meshes[k].splats = makeSplats(meshes[k]);
    out.nodes[k].splatCount = std::uint32_t(meshes[k].splats.size());
    out.payloads.push_back(storePayload(meshes[k], out.textureOwner[k] == kNoNode));
    meshes[k] = LocalMesh{};
  }
  if (options_.vdr && !out.nodes.empty()) prepareVdr(block, seam, sides, out);
  return out;
}

void HlodBuilder::prepareVdr(const Mesh& block, std::span<const glm::dvec3> seam,
                             std::span<const CutPlane> sides, PreparedBlock& out) const {
  Mesh welded = weldVertices(block);
  // Locked as the block's nodes lock it: what other blocks share, and its outline on its sides
  // (either flag locks: the vertex hierarchy never moves a locked position).
  BlockBorders borders = blockBorders(welded, seam);
  std::vector<std::uint32_t> origin(welded.positions.size());
  for (std::uint32_t v = 0; v < origin.size(); ++v) origin[v] = v;
  std::vector<std::uint8_t> locked = lockBorder(welded, origin, borders);
  markOutline(welded, origin, borders, sides, locked);
  if (welded.texture && welded.texCoords.size() == welded.positions.size())
    welded.texture = prepareNodeTexture(*welded.texture, welded.texCoords, 1.0);
  auto object = vdr::buildVdrObject(welded, locked, options_.vdrOptions);
  if (!object) {
    out.vdrError = "view-dependent object of a block: " + object.message();
    return;
  }
  out.vdr = storeVdrObject(*object);
}

Status HlodBuilder::commitBlock(PreparedBlock&& block) {
  inputTriangles_ += block.inputTriangles;
  if (block.nodes.empty()) return Ok{};
  if (!block.vdrError.empty()) return makeError(block.vdrError);
  if (skeleton_.nodes.size() + block.nodes.size() >= kNoNode) return makeError("too many nodes");
  const auto base = std::uint32_t(skeleton_.nodes.size());
  skeleton_.roots.push_back(base);
  anchors_.push_back(block.anchor);
  sides_.push_back(std::move(block.sides));
  seams_.push_back(std::move(block.seam));
  for (std::size_t k = 0; k < block.nodes.size(); ++k) {
    NodeInfo info = block.nodes[k];
    if (info.parent != kNoNode) info.parent += base;
    if (info.childCount > 0) info.firstChild += base;
    info.block = blockCount_;
    const std::uint32_t owner = block.textureOwner[k];
    if (auto s = owner == kNoNode ? writer_->appendStored(block.payloads[k], info)
                                  : writer_->appendSharingTexture(
                                        block.payloads[k], skeleton_.nodes[base + owner], info);
        !s)
      return s;
    block.payloads[k] = {};
    skeleton_.nodes.push_back(info);
  }
  if (block.vdr)
    if (auto s = writer_->appendVdr(std::move(*block.vdr), base); !s) return s;
  ++blockCount_;
  return Ok{};
}

Result<Skeleton> HlodBuilder::finish(
    double buildSeconds, const std::function<void(std::size_t, std::size_t)>& progress) {
  // An empty store would only be rejected later, by `hlodr path` and the renderer.
  if (skeleton_.nodes.empty()) return makeError("no triangles to build a store from");
  skeleton_.quadtree = quadtreeOfRoots(skeleton_, anchors_);
  std::uint64_t hlod0 = 0;
  for (std::uint32_t r : skeleton_.roots) hlod0 += skeleton_.nodes[r].numTri;
  if (options_.cells == CellMode::On ||
      (options_.cells == CellMode::Auto && hlod0 > kCellTriangles)) {
    CellPass pass{skeleton_, *writer_, *simplifier_, options_, sides_, seams_, progress};
    if (auto cells = addCellNodes(pass); !cells) return cells.error();
  }
  StoreFacts facts;
  facts.inputTriangles = inputTriangles_;
  facts.blockCount = blockCount_;
  facts.buildSeconds = buildSeconds;
  if (auto s = writer_->finish(skeleton_, facts); !s) return s.error();
  return skeleton_;
}

}  // namespace hlod
