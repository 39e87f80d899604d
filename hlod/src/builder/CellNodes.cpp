// Cell nodes above the blocks (builder/CellNodes.h): the orchestration of the cell pass.
#include "builder/CellNodes.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <unordered_map>

#include "builder/BlockBorders.h"
#include "builder/BorderStitching.h"
#include "builder/BuildingBoxes.h"
#include "builder/CellAtlas.h"
#include "builder/CellColours.h"
#include "builder/InOrderPool.h"
#include "builder/OuterSides.h"
#include "builder/Preprocess.h"
#include "builder/SimplifierImpl.h"
#include "builder/Underlay.h"
#include "hlod/parry/Splats.h"

namespace hlod {

namespace {

// A cell node under construction: the nodes below it and the blocks they hold.
struct Cell {
  std::vector<std::uint32_t> children;  // node indices, before the final ordering
  std::vector<std::uint32_t> blocks;    // NodeInfo::block of every block below
};

// Metres: a texel's cast starts at least this far in front of the cell's surface, which the
// simplification may have moved behind its children's (CellAtlas.h).
constexpr double kMinCastDepth = 0.5;

// A cell built, waiting to be appended to the store.
struct PreparedCell {
  NodeInfo info;
  StoredPayload payload;
};

// Builds a cell from its children (their NodeInfo copied before the level started: the skeleton
// grows while the level's cells are built). Thread-safe: reads what the writer flushed.
Result<PreparedCell> buildCell(
    const CellPass& pass, const Cell& cell, const std::vector<NodeInfo>& children,
    const std::vector<Aabb>& blockBoxes,
    const std::unordered_map<glm::dvec3, std::vector<std::uint32_t>, PositionHash>& seamOwners) {
  std::vector<LocalMesh> meshes;
  NodeInfo info;
  info.block = kCellBlock;
  std::uint64_t childTriangles = 0;
  for (const NodeInfo& child : children) {
    auto mesh = pass.writer.readBack(child);
    if (!mesh) return mesh.error();
    meshes.push_back(std::move(*mesh));
    info.bounds.extend(child.bounds);
    info.geometricError = std::max(info.geometricError, child.geometricError);
    childTriangles += child.numTri;
  }
  const double childError = info.geometricError;
  info.centre = info.bounds.centre();
  const ColouredMesh coloured = mergeCellChildren(meshes);
  Mesh merged = weldVertices(coloured.mesh);
  dropRepeatedTriangles(merged);
  // Locks: seam positions shared with a block outside the cell, and the outline on every side
  // of every block (a side inside the cell too: there the ground ends at the street's middle,
  // and without its outline a street between two blocks simplifies into a gap).
  std::vector<glm::dvec3> seam;
  std::vector<CutPlane> sides;
  std::vector<Aabb> boxes;
  std::vector<std::vector<CutPlane>> blockSides;
  for (std::uint32_t b : cell.blocks) {
    boxes.push_back(blockBoxes[b]);
    blockSides.push_back(pass.sides[b]);
    for (const CutPlane& c : pass.sides[b])
      if (std::none_of(sides.begin(), sides.end(),
                       [&](const CutPlane& o) { return o.axis == c.axis && o.value == c.value; }))
        sides.push_back(c);
    for (const glm::dvec3& p : pass.seams[b]) {
      const auto& owners = seamOwners.at(p + glm::dvec3(0.0));
      if (std::any_of(owners.begin(), owners.end(), [&](std::uint32_t o) {
            return !std::binary_search(cell.blocks.begin(), cell.blocks.end(), o);
          }))
        seam.push_back(p);
    }
  }
  // The payloads' positions are floats around their nodes' centres: back in doubles they lie
  // within a few ulps of the planes and seam positions the blocks were built with. Put them back
  // on them, so that the exact tests of markOutline and blockBorders find them.
  const double tolerance = kSnap * glm::length(info.bounds.size());
  snapOnto(merged, sides, seam, tolerance);
  const UpAxis up = pass.options.up.value_or(pass.skeleton.up);
  const std::vector<CutPlane> outer = outerSides(boxes, blockSides, up);
  stitchBorders(merged, sides, up, tolerance);
  BlockBorders borders = blockBorders(merged, seam);
  std::vector<std::uint32_t> origin(merged.positions.size());
  for (std::uint32_t v = 0; v < origin.size(); ++v) origin[v] = v;
  std::vector<std::uint8_t> locked = lockBorder(merged, origin, borders);
  markOutline(merged, origin, borders, outer, locked);
  const std::size_t target = std::max<std::size_t>(
      pass.options.desiredTri, childTriangles / std::size_t(pass.options.levelFactor));
  // A city's buildings become boxes (LoD1 block models), the tallest and widest first within
  // half the target; the rest of the target is the ground's.
  std::vector<BuildingBox> buildings;
  Mesh complexes;  // buildings that are no box: simplified apart from the ground
  if (!sides.empty()) {
    buildings = takeBuildings(merged, coloured.colours, up, &complexes.indices);
    complexes.positions = merged.positions;
    complexes.normals = merged.normals;
    complexes.texCoords = merged.texCoords;
    complexes.oneSided = merged.oneSided;
  }
  const std::size_t keptBoxes = std::min(buildings.size(), target / 2 / kBoxTriangles);
  double dropped = 0.0;
  for (std::size_t k = keptBoxes; k < buildings.size(); ++k)
    dropped = std::max(dropped, buildings[k].top - buildings[k].bottom);
  // The rest of the target, shared by the ground and the other buildings as their triangles.
  const std::size_t rest = std::max<std::size_t>(2, target - keptBoxes * kBoxTriangles);
  const std::size_t all = merged.triangleCount() + complexes.triangleCount();
  const auto simplifyShare = [&](const Mesh& part) {
    const std::size_t share =
        std::max<std::size_t>(1, std::size_t(double(rest) * double(part.triangleCount()) /
                                             double(std::max<std::size_t>(1, all))));
    const double factor = double(part.triangleCount()) / double(share);
    return pass.simplifier.simplifyUnion(
        part, share, locked, errorLimit(surfaceArea(part), part.triangleCount(), factor));
  };
  SimplifiedMesh simplified = simplifyShare(merged);
  if (complexes.triangleCount() > 0) {
    const SimplifiedMesh other = simplifyShare(complexes);
    simplified.geometricError = std::max(simplified.geometricError, other.geometricError);
    const auto base = std::uint32_t(simplified.mesh.positions.size());
    Mesh& m = simplified.mesh;
    m.positions.insert(m.positions.end(), other.mesh.positions.begin(), other.mesh.positions.end());
    m.normals.insert(m.normals.end(), other.mesh.normals.begin(), other.mesh.normals.end());
    m.texCoords.insert(m.texCoords.end(), other.mesh.texCoords.begin(), other.mesh.texCoords.end());
    for (std::uint32_t i : other.mesh.indices) m.indices.push_back(base + i);
  }
  info.geometricError += std::max(simplified.geometricError, dropped);
  // Without a progression (parry's would index the vertices flatColoured renumbers): a cell is
  // drawn whole.
  std::vector<glm::vec4> colours = coloured.colours;
  for (std::size_t k = 0; k < keptBoxes; ++k) appendBox(simplified.mesh, buildings[k], colours, up);
  if (!sides.empty()) addUnderlay(simplified.mesh, coloured.mesh, colours, info.bounds, up);
  simplified.mesh = flatColoured(simplified.mesh, colours);
  // The children's texture on the cell (CellAtlas.h): texels as large, on screen at the cell's
  // switch distance, as the children's at theirs, which is where its error, k times theirs, is
  // as many pixels as theirs. Without textured children the flat colours stay.
  if (const double childTexel = texelSizeOf(meshes); childTexel > 0.0) {
    CellAtlasOptions atlas;
    atlas.up = up;
    atlas.texelSize =
        childTexel * std::max(1.0, childError > 0.0 ? info.geometricError / childError : 1.0);
    atlas.castDepth = std::max(kMinCastDepth, 2.0 * atlas.texelSize);
    bakeCellAtlas(simplified.mesh, meshes, atlas);
  }
  meshes.clear();
  // The box holds what the node draws: its children's boxes, and its underlay below them.
  info.bounds.extend(simplified.mesh.bounds());
  describeNode(info, simplified.mesh, pass.options.cTex);
  LocalMesh local = localAround(simplified.mesh, info.centre);
  local.splats = makeSplats(local);
  info.splatCount = std::uint32_t(local.splats.size());
  return PreparedCell{info, storePayload(local)};
}

}  // namespace

Result<std::uint32_t> addCellNodes(CellPass& pass) {
  Skeleton& s = pass.skeleton;
  const BlockQuadtree& q = s.quadtree;
  if (q.empty()) return 0u;
  std::vector<Aabb> blockBoxes(pass.sides.size());
  for (std::uint32_t r : s.roots) blockBoxes[s.nodes[r].block] = s.nodes[r].bounds;
  std::unordered_map<glm::dvec3, std::vector<std::uint32_t>, PositionHash> seamOwners;
  for (std::uint32_t b = 0; b < pass.seams.size(); ++b)
    for (const glm::dvec3& p : pass.seams[b]) seamOwners[p + glm::dvec3(0.0)].push_back(b);

  const auto firstCell = std::uint32_t(s.nodes.size());
  std::vector<Cell> cells;                                     // per cell node
  std::vector<std::uint32_t> nodeOf(q.cells.size(), kNoNode);  // what stands for a quadtree cell
  const auto blocksBelow = [&](std::uint32_t n) {
    return n >= firstCell ? cells[n - firstCell].blocks
                          : std::vector<std::uint32_t>{s.nodes[n].block};
  };
  // q.cells is breadth-first: each quadtree level a run, every cell before its children. Levels
  // bottom up; within one, the cells from the end, as one thread would take them, built on every
  // core and committed in that order.
  std::size_t visited = 0;
  for (std::size_t end = q.cells.size(); end > 0;) {
    std::size_t begin = end - 1;
    while (begin > 0 && q.cells[begin - 1].level == q.cells[end - 1].level) --begin;
    std::vector<std::size_t> work;  // quadtree cells to build, in commit order
    std::vector<Cell> pending;
    std::vector<std::vector<NodeInfo>> childInfo;
    for (std::size_t i = end; i-- > begin;) {
      const QuadCell& c = q.cells[i];
      Cell cell;
      for (std::uint32_t k = c.firstBlock; k < c.firstBlock + c.blockCount; ++k)
        cell.children.push_back(q.blocks[k].root);
      for (std::uint32_t k = c.firstChild; k < c.firstChild + c.childCount; ++k)
        cell.children.push_back(nodeOf[k]);
      if (cell.children.size() == 1) {
        nodeOf[i] = cell.children.front();
        if (pass.progress) pass.progress(++visited, q.cells.size());
        continue;
      }
      std::vector<NodeInfo> infos;
      for (std::uint32_t n : cell.children) {
        const std::vector<std::uint32_t> below = blocksBelow(n);
        cell.blocks.insert(cell.blocks.end(), below.begin(), below.end());
        infos.push_back(s.nodes[n]);
      }
      std::sort(cell.blocks.begin(), cell.blocks.end());
      work.push_back(i);
      pending.push_back(std::move(cell));
      childInfo.push_back(std::move(infos));
    }
    if (auto f = pass.writer.flush(); !f) return f.error();
    const Status built = prepareInOrder<PreparedCell>(
        work.size(), pass.options.threads,
        [&](std::size_t k) {
          return buildCell(pass, pending[k], childInfo[k], blockBoxes, seamOwners);
        },
        [&](std::size_t k, PreparedCell&& cell) -> Status {
          if (s.nodes.size() + 1 >= kNoNode) return makeError("too many nodes");
          if (auto w = pass.writer.appendStored(cell.payload, cell.info); !w) return w;
          nodeOf[work[k]] = std::uint32_t(s.nodes.size());
          s.nodes.push_back(cell.info);
          cells.push_back(std::move(pending[k]));
          if (pass.progress) pass.progress(++visited, q.cells.size());
          return Ok{};
        },
        "cell");
    if (!built) return built.error();
    end = begin;
  }
  if (cells.empty()) return 0u;

  // Breadth-first from the top: parents before children, each node's children contiguous.
  const std::uint32_t top = nodeOf[0];
  assert(top >= firstCell);
  std::vector<std::uint32_t> order{top}, newIndex(s.nodes.size(), kNoNode);
  newIndex[top] = 0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::uint32_t n = order[i];
    const NodeInfo& info = s.nodes[n];
    const auto enqueue = [&](std::uint32_t child) {
      newIndex[child] = std::uint32_t(order.size());
      order.push_back(child);
    };
    if (n >= firstCell) {
      for (std::uint32_t c : cells[n - firstCell].children) enqueue(c);
    } else {
      for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c)
        enqueue(c);
    }
  }
  assert(order.size() == s.nodes.size());
  std::vector<NodeInfo> nodes(s.nodes.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    const std::uint32_t n = order[i];
    NodeInfo info = s.nodes[n];
    if (n >= firstCell) {
      const Cell& cell = cells[n - firstCell];
      info.firstChild = newIndex[cell.children.front()];
      info.childCount = std::uint32_t(cell.children.size());
      for (std::uint32_t c : cell.children) s.nodes[c].parent = n;
    } else if (info.childCount > 0) {
      info.firstChild = newIndex[info.firstChild];
    }
    nodes[i] = info;
  }
  // Parents last: a cell sets its children's parent above, which may come after the child.
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    const std::uint32_t parent = s.nodes[order[i]].parent;
    nodes[i].parent = parent == kNoNode ? kNoNode : newIndex[parent];
  }
  s.nodes = std::move(nodes);
  s.roots = {0};
  BlockQuadtree& tree = s.quadtree;
  for (QuadBlock& b : tree.blocks) b.root = newIndex[b.root];
  for (const QuadCell& c : tree.cells)
    std::sort(tree.blocks.begin() + c.firstBlock, tree.blocks.begin() + c.firstBlock + c.blockCount,
              [](const QuadBlock& a, const QuadBlock& b) { return a.root < b.root; });
  return std::uint32_t(cells.size());
}

}  // namespace hlod
