// Lakhia et al., "Interactive rendering of large city models", sec. III-A (model preparation)
// and III-B (per-node pre-processing).
#include "hlod/builder/HlodBuilder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <map>
#include <unordered_map>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "builder/SimplifierImpl.h"
#include "hlod/builder/PlaneSplit.h"
#include "hlod/city/City.h"

namespace hlod {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

namespace {

// A node with factor s is split into children while s > 1 (and its piece has an extent to cut).
bool isInner(double s, const Aabb& box) {
  return s > 1.0 && box.size()[longestAxis(box)] > 0.0;
}

// The children of a piece: levelFactor slabs along its longest axis, each bounded by its parent's
// planes and the slab planes on either side.
struct Children {
  SlabSplit slabs;
  std::vector<std::vector<CutPlane>> planes;  // per slab
};
Children splitPiece(const Mesh& piece, const Aabb& box, const std::vector<CutPlane>& planes,
                    int levelFactor) {
  Children c;
  c.slabs = splitIntoSlabs(piece, box, levelFactor);
  for (std::size_t k = 0; k < c.slabs.pieces.size(); ++k) {
    std::vector<CutPlane> own = planes;
    if (k > 0) own.push_back({c.slabs.axis, c.slabs.planes[k - 1]});
    if (k < c.slabs.planes.size()) own.push_back({c.slabs.axis, c.slabs.planes[k]});
    c.planes.push_back(std::move(own));
  }
  return c;
}

// One flag per vertex: on one of the piece's bounding planes (a cut shared with a neighbour).
std::vector<std::uint8_t> cutVertices(const Mesh& piece, const std::vector<CutPlane>& planes) {
  std::vector<std::uint8_t> locked(piece.positions.size(), 0);
  for (std::size_t v = 0; v < piece.positions.size(); ++v)
    for (const CutPlane& plane : planes)
      if (plane.contains(piece.positions[v])) locked[v] = 1;
  return locked;
}

// Adds the outline flags of the piece's vertices on the block's sides: kVertexOnOutline on a
// straight run of the open border there (or off the border: a kerb face lying in the side),
// kVertexLocked at a corner of it, where a collapse would cut the corner off and open a crack.
void markOutline(const Mesh& piece, const std::vector<CutPlane>& sides,
                 std::vector<std::uint8_t>& flags) {
  if (sides.empty()) return;
  std::unordered_map<glm::dvec3, std::uint32_t, PositionHash> id;
  std::vector<glm::dvec3> at;
  std::vector<std::uint32_t> idOf(piece.positions.size());
  for (std::size_t v = 0; v < piece.positions.size(); ++v) {
    auto [it, fresh] =
        id.try_emplace(piece.positions[v] + glm::dvec3(0.0), std::uint32_t(at.size()));
    if (fresh) at.push_back(piece.positions[v]);
    idOf[v] = it->second;
  }
  std::unordered_map<std::uint64_t, int> edgeUses;
  for (std::size_t i = 0; i + 2 < piece.indices.size(); i += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = idOf[piece.indices[i + k]], b = idOf[piece.indices[i + (k + 1) % 3]];
      if (a != b) ++edgeUses[(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b)];
    }
  std::vector<std::vector<std::uint32_t>> borderNeighbours(at.size());
  for (const auto& [key, uses] : edgeUses) {
    if (uses != 1) continue;
    const auto a = std::uint32_t(key >> 32), b = std::uint32_t(key & 0xffffffffu);
    borderNeighbours[a].push_back(b);
    borderNeighbours[b].push_back(a);
  }
  for (std::size_t v = 0; v < piece.positions.size(); ++v) {
    if (flags[v] == kVertexLocked) continue;
    const glm::dvec3& p = piece.positions[v];
    const CutPlane* side = nullptr;
    int n = 0;
    for (const CutPlane& c : sides)
      if (c.contains(p) && n++ == 0) side = &c;
    if (n == 0) continue;
    const auto& nb = borderNeighbours[idOf[v]];
    bool straight = n == 1 && (nb.empty() || nb.size() == 2);
    if (straight && nb.size() == 2) {
      const glm::dvec3 d0 = at[nb[0]] - p, d1 = at[nb[1]] - p;
      straight = side->contains(at[nb[0]]) && side->contains(at[nb[1]]) && glm::dot(d0, d1) < 0.0 &&
                 glm::length(glm::cross(d0, d1)) <= 1e-9 * glm::length(d0) * glm::length(d1);
    }
    flags[v] = straight ? kVertexOnOutline : kVertexLocked;
  }
}

// The error a node with simplification factor s may have: the spacing of its level's triangles
// spread evenly over the whole block (the level holds blockTriangles / s of them). A piece's own
// target does not bound it: a courtyard's paving, three large triangles in a piece, has a
// target of one, and the collapse that meets it drops 37 m of paving.
double errorLimit(double blockArea, std::size_t blockTriangles, double s) {
  return std::sqrt(blockArea * s / double(std::max<std::size_t>(1, blockTriangles)));
}

int clampedLevelFactor(const BuildOptions& options) {
  return std::max(2, options.levelFactor);
}

double rootSimplification(const Mesh& welded, const BuildOptions& options) {
  return double(welded.triangleCount()) / std::max<std::uint32_t>(1, options.desiredTri);
}

// What the slab cuts of one block may add to its triangles, in all. A cut through a pile of
// coincident triangles cuts every one of them, at every level: 20,000 copies of one quad grew
// 211-fold on the way to the leaves, 200,000 ended in bad_alloc. Once the spare (as many
// triangles as the block holds) is spent, a piece whose cut would add more stays a leaf with its
// original triangles. Both buildBlockHierarchy and planBlockSeams cut breadth-first, so both
// spend it alike and agree on every cut.
class CutSpare {
 public:
  explicit CutSpare(std::size_t triangles) : left_(triangles) {}
  // True (and spent) when the children add no more triangles than are left.
  bool take(const Mesh& piece, const Children& c) {
    std::size_t children = 0;
    for (const Mesh& m : c.slabs.pieces) children += m.triangleCount();
    const std::size_t added = children - std::min(children, piece.triangleCount());
    if (added > left_) return false;
    left_ -= added;
    return true;
  }

 private:
  std::size_t left_;
};

}  // namespace

SeamVertices planBlockSeams(const Mesh& block, const BuildOptions& options,
                            const std::vector<CutPlane>& blockPlanes) {
  // The same cuts as buildBlockHierarchy, without simplifying: only the seam vertices are kept.
  SeamVertices seams;
  struct Pending {
    Mesh piece;
    std::vector<CutPlane> planes;
    double s;
  };
  Mesh welded = weldVertices(block);
  if (welded.triangleCount() == 0) return seams;
  CutSpare spare(welded.triangleCount());
  std::deque<Pending> queue;  // breadth-first, as buildBlockHierarchy (see CutSpare)
  const double s0 = rootSimplification(welded, options);
  queue.push_back({std::move(welded), blockPlanes, s0});
  while (!queue.empty()) {
    Pending p = std::move(queue.front());
    queue.pop_front();
    seams.collect(p.piece, p.planes);
    const Aabb box = p.piece.bounds();
    if (!isInner(p.s, box)) continue;
    Children c = splitPiece(p.piece, box, p.planes, clampedLevelFactor(options));
    if (!spare.take(p.piece, c)) continue;
    for (std::size_t k = 0; k < c.slabs.pieces.size(); ++k) {
      if (c.slabs.pieces[k].triangleCount() == 0) continue;
      queue.push_back({std::move(c.slabs.pieces[k]), std::move(c.planes[k]),
                       p.s / double(clampedLevelFactor(options))});
    }
  }
  return seams;
}

std::vector<BlockNode> buildBlockHierarchy(const Mesh& block, const BuildOptions& options,
                                           const Simplifier& simplifier,
                                           const std::vector<CutPlane>& blockPlanes,
                                           const SeamVertices* neighbourSeams,
                                           const std::vector<CutPlane>& blockSides) {
  std::vector<BlockNode> nodes;
  Mesh welded = weldVertices(block);
  if (welded.triangleCount() == 0) return nodes;
  const int levelFactor = clampedLevelFactor(options);
  CutSpare spare(welded.triangleCount());
  SeamVertices seams;
  if (neighbourSeams) seams.merge(*neighbourSeams);

  const double blockArea = surfaceArea(welded);
  const std::size_t blockTriangles = welded.triangleCount();
  // Pieces waiting to become nodes: their original (cut, unsimplified) triangles.
  std::vector<Mesh> pieces;
  nodes.emplace_back();
  nodes[0].info.parent = kNoNode;
  nodes[0].simplification = rootSimplification(welded, options);  // s_hlod0
  nodes[0].planes = blockPlanes;
  pieces.push_back(std::move(welded));

  for (std::size_t i = 0; i < nodes.size(); ++i) {
    Mesh piece = std::move(pieces[i]);
    pieces[i] = Mesh{};
    const double s = nodes[i].simplification;
    const Aabb box = piece.bounds();
    nodes[i].info.bounds = box;
    nodes[i].info.centre = box.centre();
    seams.collect(piece, nodes[i].planes);
    // Children: levelFactor slabs of the piece's original triangles, s_{d+1} = s_d / levelFactor.
    // (The nodes are visited breadth-first: nodes[] grows level by level.)
    Children c;
    bool inner = isInner(s, box);
    if (inner) {
      c = splitPiece(piece, box, nodes[i].planes, levelFactor);
      inner = spare.take(piece, c);
    }
    if (inner) {
      const auto target =
          std::max<std::size_t>(1, std::size_t(std::llround(double(piece.triangleCount()) / s)));
      std::vector<std::uint8_t> locked = cutVertices(piece, nodes[i].planes);
      markOutline(piece, blockSides, locked);
      SimplifiedMesh simplified =
          simplifier.simplify(piece, target, locked, errorLimit(blockArea, blockTriangles, s));
      nodes[i].mesh = std::move(simplified.mesh);
      nodes[i].info.geometricError = simplified.geometricError;
      nodes[i].cutAxis = c.slabs.axis;
      nodes[i].cutPlanes = c.slabs.planes;
      piece = Mesh{};
      nodes[i].info.firstChild = std::uint32_t(nodes.size());
      for (std::size_t k = 0; k < c.slabs.pieces.size(); ++k) {
        if (c.slabs.pieces[k].triangleCount() == 0) continue;  // an empty slab is no node
        BlockNode n;
        n.info.parent = std::uint32_t(i);
        n.info.level = nodes[i].info.level + 1;
        n.simplification = s / double(levelFactor);
        n.planes = std::move(c.planes[k]);
        nodes.push_back(std::move(n));
        pieces.push_back(std::move(c.slabs.pieces[k]));
        ++nodes[i].info.childCount;
      }
    } else {
      nodes[i].mesh = std::move(piece);  // a leaf: the original triangles
      nodes[i].info.geometricError = 0.0;
    }
  }
  // Every node gets the seam vertices its neighbours (finer, or under other parents) have.
  for (BlockNode& n : nodes) seams.insertInto(n.mesh, n.planes);
  // A parent is never more accurate than its children: make the error monotone, bottom up.
  for (std::size_t i = nodes.size(); i-- > 1;) {
    auto& parent = nodes[nodes[i].info.parent].info;
    parent.geometricError = std::max(parent.geometricError, nodes[i].info.geometricError);
  }
  return nodes;
}

namespace {

struct MaterialKey {
  const Image* texture;
  float r, g, b, a;
  bool oneSided;
  bool operator<(const MaterialKey& o) const {
    return std::tie(texture, r, g, b, a, oneSided) <
           std::tie(o.texture, o.r, o.g, o.b, o.a, o.oneSided);
  }
};

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

// `spare`: the triangles that cuts may still add, shared by the whole recursion. A cut through
// a pile of coincident triangles cuts every one of them, so both halves can hold more triangles
// than the whole; without this bound such a pile grew by half at each of the 48 levels
// (200,000 copies of one quad ended in bad_alloc). Such a block stays whole: the triangle
// bound is a memory target, not a contract.
void splitUntilSmall(Mesh mesh, std::vector<CutPlane> planes, std::size_t maxTriangles, int depth,
                     std::size_t& spare, std::vector<Block>& out) {
  const Aabb box = mesh.bounds();
  const int axis = longestAxis(box);
  // Depth bound: triangles piled at one point cannot be separated by any plane.
  if (mesh.triangleCount() <= maxTriangles || depth >= 48 || !(box.size()[axis] > 0.0)) {
    out.push_back({std::move(mesh), std::move(planes), {}});
    return;
  }
  const CutPlane cut{axis, box.centre()[axis]};
  PlaneSplitResult halves = splitByPlane(mesh, axis, cut.value);
  const std::size_t whole = mesh.triangleCount();
  const std::size_t below = halves.below.triangleCount(), above = halves.above.triangleCount();
  const std::size_t added = below + above - std::min(below + above, whole);
  if (added > spare) {
    out.push_back({std::move(mesh), std::move(planes), {}});
    return;
  }
  spare -= added;
  mesh = Mesh{};
  planes.push_back(cut);
  if (below > 0)
    splitUntilSmall(std::move(halves.below), planes, maxTriangles, depth + 1, spare, out);
  if (above > 0)
    splitUntilSmall(std::move(halves.above), std::move(planes), maxTriangles, depth + 1, spare,
                    out);
}

}  // namespace

std::vector<Block> cutIntoBlocks(const Model& model, std::size_t maxTriangles) {
  // One texture per node payload: group meshes by material first.
  std::map<MaterialKey, Mesh> groups;
  for (const Mesh& m : model.meshes) {
    if (m.triangleCount() == 0) continue;
    const MaterialKey key{m.texture.get(), m.baseColor.r, m.baseColor.g,
                          m.baseColor.b,   m.baseColor.a, m.oneSided};
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
  for (auto& [key, mesh] : groups) {
    std::vector<Block> parts;
    std::size_t spare = mesh.triangleCount();  // cuts may at most double the triangles
    splitUntilSmall(weldVertices(mesh), {}, std::max<std::size_t>(1, maxTriangles), 0, spare,
                    parts);
    for (std::size_t i = 0; i < parts.size(); ++i) {
      if (parts.size() > 1) parts[i].mesh.name = mesh.name + "#" + std::to_string(i);
      blocks.push_back(std::move(parts[i]));
    }
  }
  return blocks;
}

Image resizeImage(const Image& image, int width, int height) {
  Image out;
  out.width = width;
  out.height = height;
  out.pixels.resize(std::size_t(width) * height * 4);
  // OpenImageIO's box filter, one destination pixel wide: each output pixel is the mean of the
  // source pixels under it. Both buffers are wrapped, not copied; one thread (the builder runs
  // blocks in sequence and owns the machine's cores for simplification).
  const OIIO::ImageBuf src(OIIO::ImageSpec(image.width, image.height, 4, OIIO::TypeDesc::UINT8),
                           const_cast<std::uint8_t*>(image.pixels.data()));
  OIIO::ImageBuf dst(OIIO::ImageSpec(width, height, 4, OIIO::TypeDesc::UINT8), out.pixels.data());
  OIIO::ImageBufAlgo::resize(dst, src, "box", 1.0f, OIIO::ROI(0, width, 0, height, 0, 1, 0, 4), 1);
  return out;
}

std::shared_ptr<const Image> prepareNodeTexture(const Image& texture,
                                                std::vector<glm::vec2>& texCoords, double factor) {
  if (texture.empty() || texture.pixels.size() != std::size_t(texture.width) * texture.height * 4)
    return nullptr;
  int x0 = 0, y0 = 0, x1 = texture.width, y1 = texture.height;
  glm::vec2 lo(1.0f), hi(0.0f);
  bool inUnit = !texCoords.empty();
  for (const auto& t : texCoords) {
    if (!(t.x >= 0.0f && t.x <= 1.0f && t.y >= 0.0f && t.y <= 1.0f)) inUnit = false;
    lo = glm::min(lo, t);
    hi = glm::max(hi, t);
  }
  if (inUnit) {
    // One texel of margin keeps bilinear filtering at the crop's edge on the right texels.
    x0 = std::max(0, int(std::floor(lo.x * texture.width)) - 1);
    y0 = std::max(0, int(std::floor(lo.y * texture.height)) - 1);
    x1 = std::min(texture.width, int(std::ceil(hi.x * texture.width)) + 1);
    y1 = std::min(texture.height, int(std::ceil(hi.y * texture.height)) + 1);
    if (x1 <= x0 || y1 <= y0) x0 = 0, y0 = 0, x1 = texture.width, y1 = texture.height;
  }
  const int cw = x1 - x0, ch = y1 - y0;
  const bool cropped = cw != texture.width || ch != texture.height;
  if (cropped) {
    for (auto& t : texCoords) {
      t.x = (t.x * float(texture.width) - float(x0)) / float(cw);
      t.y = (t.y * float(texture.height) - float(y0)) / float(ch);
    }
  }
  const double scale = factor > 1.0 ? 1.0 / std::sqrt(factor) : 1.0;
  const int w = std::min(cw, std::max(std::min(cw, kMinTextureSide), int(std::lround(cw * scale))));
  const int h = std::min(ch, std::max(std::min(ch, kMinTextureSide), int(std::lround(ch * scale))));
  if (!cropped && w == cw && h == ch) return std::make_shared<Image>(texture);
  Image crop;
  crop.width = cw;
  crop.height = ch;
  crop.pixels.resize(std::size_t(cw) * ch * 4);
  for (int y = 0; y < ch; ++y)
    std::copy_n(texture.pixels.begin() + (std::size_t(y + y0) * texture.width + x0) * 4,
                std::size_t(cw) * 4, crop.pixels.begin() + std::size_t(y) * cw * 4);
  if (w == cw && h == ch) return std::make_shared<Image>(std::move(crop));
  return std::make_shared<Image>(resizeImage(crop, w, h));
}

Result<std::unique_ptr<HlodBuilder>> HlodBuilder::create(const std::filesystem::path& dir,
                                                         const BuildOptions& options) {
  if (options.levelFactor < 2 || options.levelFactor > 64)
    return makeError("levelFactor must be an integer in [2, 64]");
  if (options.desiredTri < 1) return makeError("desiredTri must be at least 1");
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

Status HlodBuilder::addBlock(const Mesh& block, const std::vector<CutPlane>& planes,
                             const SeamVertices* neighbourSeams,
                             const std::vector<CutPlane>& sides) {
  inputTriangles_ += block.triangleCount();
  std::vector<BlockNode> local =
      buildBlockHierarchy(block, options_, *simplifier_, planes, neighbourSeams, sides);
  if (local.empty()) return Ok{};
  if (skeleton_.nodes.size() + local.size() >= kNoNode) return makeError("too many nodes");
  const auto base = std::uint32_t(skeleton_.nodes.size());
  skeleton_.roots.push_back(base);
  for (BlockNode& n : local) {
    NodeInfo info = n.info;
    if (info.parent != kNoNode) info.parent += base;
    if (info.childCount > 0) info.firstChild += base;
    info.block = blockCount_;
    const NodeMeasures m = measureNode(n.mesh, options_.cTex);
    info.numTri = m.numTri;
    info.numTexTri = m.numTexTri;
    info.cost = m.cost;
    info.staticBenefit = m.staticBenefit;
    info.avgNormal = m.avgNormal;
    LocalMesh lm = toLocal(n.mesh);
    lm.centre = info.centre;  // the piece's centre, so that node centres nest
    for (std::size_t v = 0; v < n.mesh.positions.size(); ++v)
      lm.positions[v] = glm::vec3(n.mesh.positions[v] - info.centre);
    if (n.mesh.texture && lm.texCoords.size() == lm.positions.size())
      lm.texture = prepareNodeTexture(*n.mesh.texture, lm.texCoords, n.simplification);
    else
      lm.texture = nullptr;
    n.mesh = Mesh{};
    if (auto s = writer_->appendPayload(lm, info); !s) return s;
    skeleton_.nodes.push_back(info);
  }
  ++blockCount_;
  return Ok{};
}

Result<Skeleton> HlodBuilder::finish(double buildSeconds) {
  // An empty store would only be rejected later, by `hlodr path` and the renderer.
  if (skeleton_.nodes.empty()) return makeError("no triangles to build a store from");
  StoreFacts facts;
  facts.inputTriangles = inputTriangles_;
  facts.blockCount = blockCount_;
  facts.buildSeconds = buildSeconds;
  if (auto s = writer_->finish(skeleton_, facts); !s) return s.error();
  return skeleton_;
}

namespace {

// Blocks cut from one mesh share planes: each block's nodes need the seam vertices that the cuts
// inside its neighbours put on those planes.
SeamVertices planSeams(const std::vector<Block>& blocks, const BuildOptions& options) {
  SeamVertices all;
  if (blocks.size() < 2) return all;
  for (const Block& b : blocks) all.merge(planBlockSeams(b.mesh, options, b.planes));
  return all;
}

}  // namespace

Result<Skeleton> buildStoreFromModel(const Model& model, const std::filesystem::path& dir,
                                     const BuildOptions& options, const BuildProgressFn& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  auto builder = HlodBuilder::create(dir, options);
  if (!builder) return builder.error();
  (*builder)->setModelFrame(upAxisOf(model), model.crs);
  std::vector<Block> blocks = cutIntoBlocks(model, options.maxBlockTriangles);
  BuildProgress p;
  p.blockCount = blocks.size();
  const SeamVertices seams = planSeams(blocks, options);
  for (Block& block : blocks) {
    if (auto s = (*builder)->addBlock(block.mesh, block.planes, &seams); !s) return s.error();
    p.trianglesDone += block.mesh.triangleCount();
    block = Block{};
    ++p.blocksDone;
    p.seconds = secondsSince(t0);
    if (progress) progress(p);
  }
  return (*builder)->finish(secondsSince(t0));
}

Result<Skeleton> buildStoreFromCity(const std::filesystem::path& cityDir,
                                    const std::filesystem::path& dir, const BuildOptions& options,
                                    const BuildProgressFn& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  auto manifest = readCityManifest(cityDir);
  if (!manifest) return manifest.error();
  if (manifest->blocks.empty())
    return makeError((cityDir / "city.json").string() +
                     " lists no blocks: no triangles to build a store from");
  auto builder = HlodBuilder::create(dir, options);
  if (!builder) return builder.error();
  BuildProgress p;
  p.blockCount = manifest->blocks.size();
  for (std::size_t i = 0; i < manifest->blocks.size(); ++i) {
    // One block in memory at a time: load, build its subtree, free.
    auto block = loadCityBlock(*manifest, i);
    if (!block) return block.error();
    // A city block is one texture already; split only blocks over the bound.
    Model one;
    one.meshes.push_back(std::move(*block));
    std::vector<Block> parts = cutIntoBlocks(one, options.maxBlockTriangles);
    // A city block's sides (the middles of its streets, on its box) meet its neighbours' ground.
    const Aabb box = one.bounds();
    for (Block& part : parts)
      for (int axis = 0; axis < 2; ++axis)
        for (double v : {box.min[axis], box.max[axis]}) part.sides.push_back({axis, v});
    const SeamVertices seams = planSeams(parts, options);
    for (const Block& part : parts) {
      if (auto s = (*builder)->addBlock(part.mesh, part.planes, &seams, part.sides); !s)
        return s.error();
      p.trianglesDone += part.mesh.triangleCount();
    }
    ++p.blocksDone;
    p.seconds = secondsSince(t0);
    if (progress) progress(p);
  }
  return (*builder)->finish(secondsSince(t0));
}

}  // namespace hlod
