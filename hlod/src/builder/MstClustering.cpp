// Stage 2 of Manocha sec. 2.2: Felzenszwalb and Huttenlocher's MST clustering over objects
// (builder/MstClustering.h).
#include "builder/MstClustering.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numeric>
#include <tuple>
#include <unordered_map>

namespace hlod {

namespace {

// A uniform grid of cells h wide over the items' boxes: each item listed in every cell its box
// touches, or among the `large` ones when that is more than kMaxCellsPerItem cells (a floor slab
// under everything), which every query sees.
constexpr std::int64_t kMaxCellsPerItem = 4096;

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey&) const = default;
};
struct CellKeyHash {
  std::size_t operator()(const CellKey& c) const {
    return std::size_t(c.x * 73856093 ^ c.y * 19349663 ^ c.z * 83492791);
  }
};

class Grid {
 public:
  Grid(std::span<const PartitionItem> items, double h) : items_(items), h_(h) {
    for (const PartitionItem& it : items) scene_.extend(it.box);
    for (std::uint32_t i = 0; i < items.size(); ++i) {
      const auto [lo, hi] = range(items[i].box);
      if (count(lo, hi) > kMaxCellsPerItem) {
        large_.push_back(i);
        continue;
      }
      for (std::int64_t x = lo.x; x <= hi.x; ++x)
        for (std::int64_t y = lo.y; y <= hi.y; ++y)
          for (std::int64_t z = lo.z; z <= hi.z; ++z) cells_[{x, y, z}].push_back(i);
    }
  }

  // Calls f(j) for every item whose box may lie within r of `box` (some more than once), until
  // f returns true.
  template <class F>
  void near(const Aabb& box, double r, F&& f) const {
    Aabb q = box;
    q.min -= glm::dvec3(r);
    q.max += glm::dvec3(r);
    const auto [lo, hi] = range(q);
    for (std::uint32_t j : large_)
      if (f(j)) return;
    if (count(lo, hi) > std::int64_t(cells_.size())) {
      for (const auto& [key, list] : cells_)
        if (key.x >= lo.x && key.x <= hi.x && key.y >= lo.y && key.y <= hi.y && key.z >= lo.z &&
            key.z <= hi.z)
          for (std::uint32_t j : list)
            if (f(j)) return;
      return;
    }
    for (std::int64_t x = lo.x; x <= hi.x; ++x)
      for (std::int64_t y = lo.y; y <= hi.y; ++y)
        for (std::int64_t z = lo.z; z <= hi.z; ++z)
          if (auto it = cells_.find({x, y, z}); it != cells_.end())
            for (std::uint32_t j : it->second)
              if (f(j)) return;
  }
  double sceneDiagonal() const { return glm::length(scene_.size()); }

 private:
  // Cells of a box, clamped to the scene's (a query box reaching past it finds nothing there).
  std::pair<CellKey, CellKey> range(const Aabb& b) const {
    const auto cell = [&](double v, double origin) {
      return std::int64_t(std::floor(std::clamp((v - origin) / h_, -1.0, 1e9)));
    };
    const glm::dvec3 lo = glm::max(b.min, scene_.min), hi = glm::min(b.max, scene_.max);
    return {{cell(lo.x, scene_.min.x), cell(lo.y, scene_.min.y), cell(lo.z, scene_.min.z)},
            {cell(hi.x, scene_.min.x), cell(hi.y, scene_.min.y), cell(hi.z, scene_.min.z)}};
  }
  static std::int64_t count(const CellKey& lo, const CellKey& hi) {
    const auto n = [](std::int64_t a, std::int64_t b) {
      return std::max<std::int64_t>(0, b - a + 1);
    };
    const std::int64_t nx = n(lo.x, hi.x), ny = n(lo.y, hi.y), nz = n(lo.z, hi.z);
    // Saturating: a query over the whole scene must not overflow.
    if (nx > 0 && ny > (std::int64_t(1) << 62) / nx) return std::int64_t(1) << 62;
    if (nx * ny > 0 && nz > (std::int64_t(1) << 62) / (nx * ny)) return std::int64_t(1) << 62;
    return nx * ny * nz;
  }

  std::span<const PartitionItem> items_;
  double h_;
  Aabb scene_;
  std::unordered_map<CellKey, std::vector<std::uint32_t>, CellKeyHash> cells_;
  std::vector<std::uint32_t> large_;
};

struct Edge {
  double w;       // box gap
  double centre;  // distance between the centres: the tie-break
  std::uint32_t a, b;
  bool operator<(const Edge& o) const {
    return std::tie(w, centre, a, b) < std::tie(o.w, o.centre, o.a, o.b);
  }
};

// The nearest-neighbour graph: each item joined to its `neighbours` nearest by box gap.
std::vector<Edge> nearestNeighbourGraph(std::span<const PartitionItem> items, int neighbours) {
  Aabb scene;
  std::vector<double> sides;
  for (const PartitionItem& it : items) {
    scene.extend(it.box);
    const glm::dvec3 s = it.box.size();
    sides.push_back(std::max({s.x, s.y, s.z}));
  }
  std::nth_element(sides.begin(), sides.begin() + std::ptrdiff_t(sides.size() / 2), sides.end());
  // Cells about as large as an object, and few enough: about one item per cell.
  const double diagonal = glm::length(scene.size());
  double h =
      std::max(sides[sides.size() / 2], diagonal / std::max(1.0, std::cbrt(double(items.size()))));
  if (!(h > 0.0)) h = 1.0;
  const Grid grid(items, h);
  std::vector<Edge> edges;
  // stamp[j] == query: j seen by this query already (each ring of each item is a query).
  std::vector<std::uint64_t> stamp(items.size(), 0);
  std::uint64_t query = 0;
  std::vector<Edge> found;
  for (std::uint32_t i = 0; i < items.size(); ++i) {
    for (double r = h;; r *= 2.0) {
      found.clear();
      ++query;
      // Enough touching neighbours (gap 0, none nearer) end the query: a pile of objects in one
      // cell would otherwise make the graph quadratic. Their tie-break is then the grid's order.
      std::size_t touching = 0;
      grid.near(items[i].box, r, [&](std::uint32_t j) {
        if (j == i || stamp[j] == query) return false;
        stamp[j] = query;
        const double w = boxGap(items[i].box, items[j].box);
        if (w <= r)
          found.push_back(
              {w, glm::length(items[i].centre - items[j].centre), std::min(i, j), std::max(i, j)});
        if (w == 0.0) ++touching;
        return touching >= std::size_t(neighbours);
      });
      if (found.size() >= std::size_t(neighbours) || r > diagonal) break;
    }
    const std::size_t keep = std::min(found.size(), std::size_t(neighbours));
    std::partial_sort(found.begin(), found.begin() + std::ptrdiff_t(keep), found.end());
    edges.insert(edges.end(), found.begin(), found.begin() + std::ptrdiff_t(keep));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end(),
                          [](const Edge& x, const Edge& y) { return x.a == y.a && x.b == y.b; }),
              edges.end());
  return edges;
}

}  // namespace

double boxGap(const Aabb& a, const Aabb& b) {
  const glm::dvec3 d = glm::max(glm::dvec3(0.0), glm::max(a.min - b.max, b.min - a.max));
  return glm::length(d);
}

std::vector<std::vector<std::uint32_t>> clusterByMst(std::span<const PartitionItem> items,
                                                     const MstClusteringOptions& options) {
  assert(options.k >= 0.0 && options.neighbours >= 1);
  std::vector<std::vector<std::uint32_t>> out;
  if (items.empty()) return out;
  const std::vector<Edge> edges = nearestNeighbourGraph(items, options.neighbours);
  // A disjoint-set forest; per root: |C|, Int(C) and the cluster's triangles.
  std::vector<std::uint32_t> parent(items.size());
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<std::uint32_t> size(items.size(), 1);
  std::vector<double> internal(items.size(), 0.0);  // Int(C)
  std::vector<std::uint64_t> triangles(items.size());
  for (std::size_t i = 0; i < items.size(); ++i) triangles[i] = items[i].triangles;
  const auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  const auto tau = [&](std::uint32_t c) { return options.k / double(size[c]); };
  // Kruskal's order: a merging edge is the heaviest of the merged cluster's tree so far.
  for (const Edge& e : edges) {
    std::uint32_t a = find(e.a), b = find(e.b);
    if (a == b) continue;
    const double mInt = std::min(internal[a] + tau(a), internal[b] + tau(b));
    if (e.w > mInt || triangles[a] + triangles[b] > options.maxTriangles) continue;
    if (size[a] < size[b]) std::swap(a, b);
    parent[b] = a;
    size[a] += size[b];
    triangles[a] += triangles[b];
    internal[a] = e.w;  // edges come in non-decreasing weight: the largest in its tree
  }
  std::vector<std::uint32_t> clusterOf(items.size(), 0xffffffffu);
  for (std::uint32_t i = 0; i < items.size(); ++i) {
    std::uint32_t& c = clusterOf[find(i)];
    if (c == 0xffffffffu) {
      c = std::uint32_t(out.size());
      out.emplace_back();
    }
    out[c].push_back(i);
  }
  return out;
}

}  // namespace hlod
