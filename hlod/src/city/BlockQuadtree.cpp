// Parry et al. sec. 3: the global quadtree of city blocks (hlod/city/BlockQuadtree.h).
#include "hlod/city/BlockQuadtree.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <set>

#include "hlod/geodesy/Geodesy.h"

namespace hlod {

double wrapLongitude(double lon) {
  if (lon >= -180.0 && lon < 180.0) return lon;
  const double w = std::fmod(lon + 180.0, 360.0);
  return (w < 0.0 ? w + 360.0 : w) - 180.0;
}

glm::uvec2 quadCellAt(const QuadRect& rect, std::uint32_t level, const glm::dvec2& anchor) {
  assert(level <= kMaxQuadtreeDepth);
  const double n = std::ldexp(1.0, int(level));
  const auto index = [&](double a, double lo, double hi) {
    const double f = std::floor((a - lo) / (hi - lo) * n);
    return std::uint32_t(std::clamp(f, 0.0, n - 1.0));
  };
  return {index(anchor.x, rect.minU, rect.maxU), index(anchor.y, rect.minV, rect.maxV)};
}

QuadRect quadCellRect(const QuadRect& rect, std::uint32_t level, std::uint32_t x, std::uint32_t y) {
  const double n = std::ldexp(1.0, int(level));
  const double w = (rect.maxU - rect.minU) / n, h = (rect.maxV - rect.minV) / n;
  return {rect.minU + w * x, rect.minV + h * y, rect.minU + w * (x + 1.0),
          rect.minV + h * (y + 1.0)};
}

std::uint32_t quadtreeDepthFor(double rectMetres, double blockSize) {
  if (!(rectMetres > 0.0) || !(blockSize > 0.0) || !std::isfinite(rectMetres / blockSize)) return 0;
  const double d = std::round(std::log2(rectMetres / blockSize));
  return std::uint32_t(std::clamp(d, 0.0, double(kMaxQuadtreeDepth)));
}

QuadRect squareAround(std::span<const QuadBlockInput> blocks) {
  glm::dvec2 lo(0.0), hi(0.0);
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    lo = i ? glm::min(lo, blocks[i].anchor) : blocks[i].anchor;
    hi = i ? glm::max(hi, blocks[i].anchor) : blocks[i].anchor;
  }
  // Far from the origin a side of 1 may vanish beside lo (lo + 1 == lo: a square of no width,
  // and 0/0 cell indices): at least a few of lo's units in the last place.
  const auto ulp = [](double v) {
    return std::nextafter(std::abs(v), std::numeric_limits<double>::infinity()) - std::abs(v);
  };
  double side = std::max({hi.x - lo.x, hi.y - lo.y, 1.0, 4.0 * ulp(lo.x), 4.0 * ulp(lo.y)});
  // Far from the origin lo + side may round below hi (the store's codec then finds an anchor
  // outside the rectangle): grow the side until the square holds every anchor.
  const bool finite =
      std::isfinite(lo.x) && std::isfinite(lo.y) && std::isfinite(hi.x) && std::isfinite(hi.y);
  while (finite && (lo.x + side < hi.x || lo.y + side < hi.y)) side *= 1.0 + 1e-12;
  return {lo.x, lo.y, lo.x + side, lo.y + side};
}

BlockQuadtree buildBlockQuadtree(QuadtreeDomain domain, const QuadRect& rect, std::uint32_t depth,
                                 std::span<const QuadBlockInput> blocks) {
  assert(domain != QuadtreeDomain::None && depth <= kMaxQuadtreeDepth);
  BlockQuadtree tree;
  tree.domain = domain;
  tree.rect = rect;
  tree.depth = depth;
  if (blocks.empty()) return tree;
  // Each block's leaf cell as a Morton code (row and column bits interleaved, the coarsest
  // first): the blocks of any cell are then one run of the sorted list, its quadrants in order.
  struct Placed {
    std::uint64_t morton;
    QuadBlockInput block;
  };
  std::vector<Placed> placed;
  for (QuadBlockInput b : blocks) {
    if (domain == QuadtreeDomain::Geographic) b.anchor.x = wrapLongitude(b.anchor.x);
    const glm::uvec2 c = quadCellAt(rect, depth, b.anchor);
    std::uint64_t m = 0;
    for (int bit = int(depth) - 1; bit >= 0; --bit)
      m = (m << 2) | (std::uint64_t((c.y >> bit) & 1u) << 1) | ((c.x >> bit) & 1u);
    placed.push_back({m, b});
  }
  std::sort(placed.begin(), placed.end(), [](const Placed& a, const Placed& b) {
    return a.morton != b.morton ? a.morton < b.morton : a.block.root < b.block.root;
  });
  for (const Placed& p : placed) tree.blocks.push_back({p.block.root, p.block.anchor});

  // Breadth first: each cell with its run of blocks [begin, end).
  struct Pending {
    std::uint32_t cell;
    std::size_t begin, end;
  };
  tree.cells.push_back(QuadCell{});
  std::vector<Pending> queue{{0, 0, placed.size()}};
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const Pending p = queue[head];
    QuadCell& cell = tree.cells[p.cell];
    if (cell.level == depth) {
      cell.firstBlock = std::uint32_t(p.begin);
      cell.blockCount = std::uint32_t(p.end - p.begin);
      for (std::size_t i = p.begin; i < p.end; ++i) cell.bounds.extend(placed[i].block.bounds);
      continue;
    }
    const int shift = 2 * int(depth - cell.level - 1);
    const QuadCell parent = cell;  // cells grows below
    tree.cells[p.cell].firstChild = std::uint32_t(tree.cells.size());
    for (std::size_t i = p.begin; i < p.end;) {
      const auto quadrant = std::uint32_t((placed[i].morton >> shift) & 3u);
      std::size_t j = i;
      while (j < p.end && ((placed[j].morton >> shift) & 3u) == quadrant) ++j;
      QuadCell child;
      child.level = parent.level + 1;
      child.x = parent.x * 2 + (quadrant & 1u);
      child.y = parent.y * 2 + (quadrant >> 1);
      queue.push_back({std::uint32_t(tree.cells.size()), i, j});
      tree.cells.push_back(child);
      ++tree.cells[p.cell].childCount;
      i = j;
    }
  }
  // Boxes bottom up: children come after their parents.
  for (std::size_t i = tree.cells.size(); i-- > 0;) {
    const QuadCell& c = tree.cells[i];
    for (std::uint32_t k = c.firstChild; k < c.firstChild + c.childCount; ++k)
      tree.cells[i].bounds.extend(tree.cells[k].bounds);
  }
  return tree;
}

QuadtreeStats quadtreeStats(const BlockQuadtree& tree) {
  QuadtreeStats st;
  st.cells = tree.cells.size();
  if (tree.empty()) return st;
  const double n = std::ldexp(1.0, int(tree.depth));
  st.leafSize = {(tree.rect.maxU - tree.rect.minU) / n, (tree.rect.maxV - tree.rect.minV) / n};
  std::set<std::pair<double, double>> all;
  double latSum = 0.0;
  for (std::size_t i = 0; i < tree.blocks.size(); ++i) {
    const glm::dvec2 a = tree.blocks[i].anchor;
    st.anchors = i == 0 ? QuadRect{a.x, a.y, a.x, a.y}
                        : QuadRect{std::min(st.anchors.minU, a.x), std::min(st.anchors.minV, a.y),
                                   std::max(st.anchors.maxU, a.x), std::max(st.anchors.maxV, a.y)};
    all.insert({a.x, a.y});
    latSum += a.y;
  }
  st.blocks = all.size();
  for (const QuadCell& c : tree.cells) {
    if (c.childCount > 0) continue;
    ++st.leafCells;
    std::set<std::pair<double, double>> here;
    for (std::uint32_t k = c.firstBlock; k < c.firstBlock + c.blockCount; ++k)
      here.insert({tree.blocks[k].anchor.x, tree.blocks[k].anchor.y});
    st.maxBlocks = std::max(st.maxBlocks, here.size());
    st.maxRoots = std::max<std::size_t>(st.maxRoots, c.blockCount);
  }
  if (st.leafCells > 0) {
    st.meanBlocks = double(st.blocks) / double(st.leafCells);
    st.meanRoots = double(tree.blocks.size()) / double(st.leafCells);
  }
  if (tree.domain == QuadtreeDomain::Geographic && !tree.blocks.empty()) {
    // A degree along a parallel and along a meridian at the mean latitude (WGS 84).
    const double lat = latSum / double(tree.blocks.size()) * kRadPerDeg;
    const double w = 1.0 - kWgs84E2 * std::sin(lat) * std::sin(lat);
    const double east = kWgs84A * std::cos(lat) / std::sqrt(w) * kRadPerDeg;
    const double north = kWgs84A * (1.0 - kWgs84E2) / (w * std::sqrt(w)) * kRadPerDeg;
    st.leafMetres = {st.leafSize.x * east, st.leafSize.y * north};
  }
  return st;
}

}  // namespace hlod
