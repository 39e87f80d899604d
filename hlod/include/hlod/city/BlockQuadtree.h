#pragma once
// The global quadtree of city blocks (Parry et al., "Organization and Simplification of
// High-Resolution 3D City Facades", sec. 3): "Each city block contains a latitude and longitude
// position and is inserted into our global quadtree based on this position. We choose the depth
// of the tree such that the size of the smallest quadnode is roughly the size of a city block."
//
// The root covers the whole globe, longitude [-180, 180] by latitude [-90, 90]; each cell
// divides into four equal quarters in degrees. Only cells that hold blocks exist, and blocks sit
// in the cells of the deepest level (`depth`). A model without a geographic anchor (a mesh file,
// an unknown projected CRS) gets the same tree over its own horizontal coordinates instead
// (QuadtreeDomain::Model: a square around its blocks).
//
// Each cell keeps the world-space box of its blocks (the union of their hlod_0 nodes' boxes), so
// that frustum culling can skip a whole cell; the blocks are the hlod_0 nodes (Skeleton::roots),
// several per block when a block is split by material or size.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"

namespace hlod {

enum class QuadtreeDomain : std::uint32_t {
  None = 0,        // no quadtree: every block root is visited
  Geographic = 1,  // anchors are (longitude, latitude) in degrees, WGS 84
  Model = 2,       // anchors are the model's own horizontal coordinates
};

// A rectangle of anchors: u along longitude (or the model's first horizontal axis), v along
// latitude (or its second).
struct QuadRect {
  double minU = 0.0, minV = 0.0, maxU = 0.0, maxV = 0.0;
  bool operator==(const QuadRect&) const = default;
};
inline constexpr QuadRect kWholeGlobe{-180.0, -90.0, 180.0, 90.0};
// 2^30 cells a side: 2 cm of latitude, far below any block.
inline constexpr std::uint32_t kMaxQuadtreeDepth = 30;
// Half a meridian of WGS 84 (the root's north-south side), metres.
inline constexpr double kHalfMeridianMetres = 20003931.458;

struct QuadCell {
  std::uint32_t level = 0;     // 0: the root
  std::uint32_t x = 0, y = 0;  // column (u) and row (v) at its level, each in [0, 2^level)
  std::uint32_t firstChild = 0, childCount = 0;  // children contiguous in cells, one a quadrant
  std::uint32_t firstBlock = 0, blockCount = 0;  // its blocks in BlockQuadtree::blocks (leaves)
  Aabb bounds;  // world space: the union of its blocks' hlod_0 boxes
};

struct QuadBlock {
  std::uint32_t root = 0;  // the block's hlod_0 node
  glm::dvec2 anchor{0.0};  // (lon, lat) in degrees, or the model's (u, v)
};

struct BlockQuadtree {
  QuadtreeDomain domain = QuadtreeDomain::None;
  QuadRect rect;
  std::uint32_t depth = 0;        // the level of the cells that hold blocks
  std::vector<QuadCell> cells;    // cells[0] is the root; children after their parent
  std::vector<QuadBlock> blocks;  // grouped by leaf cell

  bool empty() const { return cells.empty(); }
};

// A longitude in [-180, 180).
double wrapLongitude(double lon);

// The (column, row) of the cell at `level` that holds `anchor`: floor of its position in cells,
// clamped, so that the far edges (longitude 180, latitude 90) belong to the last cells.
glm::uvec2 quadCellAt(const QuadRect& rect, std::uint32_t level, const glm::dvec2& anchor);
// The rectangle of cell (x, y) at `level`.
QuadRect quadCellRect(const QuadRect& rect, std::uint32_t level, std::uint32_t x, std::uint32_t y);

// The depth whose cells' v side is nearest a block: round(log2(rectMetres / blockSize)),
// clamped to [0, kMaxQuadtreeDepth], where rectMetres is the root's v side in metres (the
// globe: kHalfMeridianMetres, so 100 m blocks give depth 18, cells of 76 m north-south and
// 153 m * cos(latitude) east-west). With cells about a block, a block overlaps up to four
// cells, as in Parry.
std::uint32_t quadtreeDepthFor(double rectMetres, double blockSize);

// A block to insert: its hlod_0 node, anchor and world box.
struct QuadBlockInput {
  std::uint32_t root = 0;
  glm::dvec2 anchor{0.0};
  Aabb bounds;
};

// The quadtree of `blocks` (each anchor inside rect; geographic longitudes wrapped first),
// blocks in the cells at `depth` that hold their anchors, each cell's box the union of its
// blocks' (and children's) boxes. Cells in breadth-first order; a leaf's blocks by root id.
BlockQuadtree buildBlockQuadtree(QuadtreeDomain domain, const QuadRect& rect, std::uint32_t depth,
                                 std::span<const QuadBlockInput> blocks);

// A square around the anchors for QuadtreeDomain::Model (side at least 1).
QuadRect squareAround(std::span<const QuadBlockInput> blocks);

// What `hlodr info` shows of a quadtree.
struct QuadtreeStats {
  std::size_t cells = 0, leafCells = 0;
  // The smallest cells' sides: in degrees (geographic: longitude, latitude) or model units.
  glm::dvec2 leafSize{0.0};
  // Geographic: the same in metres at the blocks' mean latitude (east-west, north-south).
  glm::dvec2 leafMetres{0.0};
  // Per leaf cell: blocks (distinct anchors) and roots (hlod_0 nodes), max and mean.
  std::size_t maxBlocks = 0, maxRoots = 0;
  double meanBlocks = 0.0, meanRoots = 0.0;
  std::size_t blocks = 0;  // distinct anchors
  QuadRect anchors;        // the anchors' extent
};
QuadtreeStats quadtreeStats(const BlockQuadtree& tree);

}  // namespace hlod
