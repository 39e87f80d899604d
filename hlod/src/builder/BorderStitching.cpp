// Welding a cell's children along their shared sides (builder/BorderStitching.h).
#include "builder/BorderStitching.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "builder/SimplifierImpl.h"

namespace hlod {

void snapOnto(Mesh& mesh, std::span<const CutPlane> planes, std::span<const glm::dvec3> points,
              double tolerance) {
  // Points in a grid of cells `tolerance` wide: a point within it lies in one of 27 cells.
  const auto cellOf = [&](const glm::dvec3& p) { return glm::i64vec3(glm::floor(p / tolerance)); };
  struct CellHash {
    std::size_t operator()(const glm::i64vec3& c) const {
      return std::size_t(c.x * 73856093 ^ c.y * 19349663 ^ c.z * 83492791);
    }
  };
  std::unordered_map<glm::i64vec3, std::vector<glm::dvec3>, CellHash> grid;
  if (tolerance > 0.0)
    for (const glm::dvec3& p : points) grid[cellOf(p)].push_back(p);
  for (glm::dvec3& p : mesh.positions) {
    for (const CutPlane& c : planes)
      if (std::abs(p[c.axis] - c.value) <= tolerance) p[c.axis] = c.value;
    if (grid.empty()) continue;
    const glm::i64vec3 at = cellOf(p);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          if (auto it = grid.find(at + glm::i64vec3(dx, dy, dz)); it != grid.end())
            for (const glm::dvec3& q : it->second)
              if (glm::length(q - p) <= tolerance) p = q;
  }
}

void stitchBorders(Mesh& mesh, std::span<const CutPlane> planes, UpAxis up, double tolerance) {
  // Position ids, and the open-border edges by position: an edge one triangle uses.
  std::unordered_map<glm::dvec3, std::uint32_t, PositionHash> id;
  std::vector<std::uint32_t> pid(mesh.positions.size());
  std::vector<std::uint32_t> vertexAt;  // a vertex per position id
  for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
    auto [it, fresh] =
        id.try_emplace(mesh.positions[v] + glm::dvec3(0.0), std::uint32_t(id.size()));
    if (fresh) vertexAt.push_back(v);
    pid[v] = it->second;
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;  // (position pair, corner)
  for (std::uint32_t c = 0; c < mesh.indices.size(); ++c) {
    const std::uint32_t a = pid[mesh.indices[c]], b = pid[mesh.indices[c - c % 3 + (c + 1) % 3]];
    edges.emplace_back(std::uint64_t(std::min(a, b)) << 32 | std::max(a, b), c);
  }
  std::sort(edges.begin(), edges.end());
  std::vector<std::uint32_t> borderCorners;  // corner c: the edge from c to the next corner
  std::vector<std::uint8_t> onBorder(id.size(), 0);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t end = i + 1;
    while (end < edges.size() && edges[end].first == edges[i].first) ++end;
    if (end - i == 1) {
      borderCorners.push_back(edges[i].second);
      onBorder[edges[i].first >> 32] = onBorder[edges[i].first & 0xffffffffu] = 1;
    }
    i = end;
  }
  // Per border edge on a plane, the border positions strictly inside it.
  struct CornerSplit {
    double t;
    std::uint32_t position;
  };
  std::unordered_map<std::uint32_t, std::vector<CornerSplit>> splits;  // by corner
  for (const CutPlane& plane : planes) {
    const int along = 3 - plane.axis - int(up);  // the horizontal axis the plane runs along
    std::vector<std::uint32_t> points;
    for (std::uint32_t p = 0; p < id.size(); ++p)
      if (onBorder[p] && plane.contains(mesh.positions[vertexAt[p]])) points.push_back(p);
    const auto at = [&](std::uint32_t p) { return mesh.positions[vertexAt[p]][along]; };
    std::sort(points.begin(), points.end(),
              [&](std::uint32_t a, std::uint32_t b) { return at(a) < at(b); });
    for (std::uint32_t c : borderCorners) {
      const glm::dvec3 a = mesh.positions[mesh.indices[c]];
      const glm::dvec3 b = mesh.positions[mesh.indices[c - c % 3 + (c + 1) % 3]];
      if (!plane.contains(a) || !plane.contains(b)) continue;
      const double lo = std::min(a[along], b[along]), hi = std::max(a[along], b[along]);
      const glm::dvec3 d = b - a;
      const double len2 = glm::dot(d, d);
      if (!(len2 > 0.0)) continue;
      auto it = std::lower_bound(points.begin(), points.end(), lo,
                                 [&](std::uint32_t p, double v) { return at(p) < v; });
      for (; it != points.end() && at(*it) <= hi; ++it) {
        const glm::dvec3 q = mesh.positions[vertexAt[*it]];
        const double t = glm::dot(q - a, d) / len2;
        if (t <= 1e-9 || t >= 1.0 - 1e-9 || glm::length(a + t * d - q) > tolerance) continue;
        splits[c].push_back({t, *it});
      }
    }
  }
  // Each split triangle becomes a fan from the corner opposite its border edge.
  std::vector<std::uint32_t> indices;
  indices.reserve(mesh.indices.size());
  for (std::uint32_t t = 0; t * 3 < mesh.indices.size(); ++t) {
    std::uint32_t split = 3;
    for (std::uint32_t k = 0; k < 3; ++k)
      if (splits.count(3 * t + k)) split = split == 3 ? k : 4;  // 4: more than one edge
    const std::uint32_t* tri = &mesh.indices[3 * t];
    if (split >= 3) {
      indices.insert(indices.end(), tri, tri + 3);
      continue;
    }
    std::vector<CornerSplit>& points = splits[3 * t + split];
    std::sort(points.begin(), points.end(),
              [](const CornerSplit& x, const CornerSplit& y) { return x.t < y.t; });
    const std::uint32_t a = tri[split], b = tri[(split + 1) % 3], c = tri[(split + 2) % 3];
    std::uint32_t prev = a;
    for (const CornerSplit& p : points) {
      // The new vertex: the other side's position, with the attributes of the nearer end.
      const std::uint32_t from = p.t < 0.5 ? a : b;
      const auto v = std::uint32_t(mesh.positions.size());
      mesh.positions.push_back(mesh.positions[vertexAt[p.position]]);
      if (!mesh.normals.empty()) mesh.normals.push_back(mesh.normals[from]);
      if (!mesh.texCoords.empty()) mesh.texCoords.push_back(mesh.texCoords[from]);
      indices.insert(indices.end(), {prev, v, c});
      prev = v;
    }
    indices.insert(indices.end(), {prev, b, c});
  }
  mesh.indices = std::move(indices);
}

}  // namespace hlod
