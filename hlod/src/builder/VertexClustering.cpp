#include "hlod/builder/VertexClustering.h"

#include <algorithm>
#include <limits>
#include <unordered_map>

#include <glm/glm.hpp>

namespace hlod {

namespace {

// The triangles left when every unlocked vertex moves to a representative of its cell in a grid
// of `cells` cells along the longest side (locked vertices stay). Degenerate and repeated
// triangles go. The representative is the cell's vertex nearest the cell's mean position.
// The axis a vertex's surface faces most, with its sign (0..5): the area-weighted normal of its
// triangles. Both sides of a thin slab, a wall and the box against it, face different ways.
std::vector<std::uint8_t> facingAxis(const Simplifier::Shape& shape,
                                     const std::vector<std::uint32_t>& indices) {
  std::vector<glm::dvec3> normal(shape.positions.size(), glm::dvec3(0.0));
  for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
    const glm::dvec3& a = shape.positions[indices[i]];
    const glm::dvec3 n =
        glm::cross(shape.positions[indices[i + 1]] - a, shape.positions[indices[i + 2]] - a);
    for (int k = 0; k < 3; ++k) normal[indices[i + k]] += n;
  }
  std::vector<std::uint8_t> axis(shape.positions.size(), 0);
  for (std::size_t v = 0; v < normal.size(); ++v) {
    const glm::dvec3 n = normal[v], m = glm::abs(n);
    const int a = m.x >= m.y && m.x >= m.z ? 0 : m.y >= m.z ? 1 : 2;
    axis[v] = std::uint8_t(2 * a + (n[a] < 0.0 ? 1 : 0));
  }
  return axis;
}

Simplifier::ReducedShape clusterOnGrid(const Simplifier::Shape& shape,
                                       const std::vector<std::uint32_t>& indices,
                                       const std::vector<std::uint8_t>& axisOf, int cells) {
  Aabb box;
  for (std::uint32_t v : indices) box.extend(shape.positions[v]);
  const glm::dvec3 size = box.size();
  const double cell = std::max({size.x, size.y, size.z}) / cells;
  std::unordered_map<std::uint64_t, std::uint32_t> cellIndex;
  std::vector<std::uint32_t> cellOf(shape.positions.size(), 0xffffffffu);
  std::vector<glm::dvec3> sum;
  std::vector<std::uint32_t> count;
  for (std::uint32_t v : indices) {
    if (cellOf[v] != 0xffffffffu) continue;
    std::uint64_t key;
    if (shape.locked[v]) {
      key = (1ull << 63) | v;  // a cell of its own
    } else {
      const glm::dvec3 q = (shape.positions[v] - box.min) / cell;
      auto c = [&](double x) { return std::uint64_t(std::clamp(x, 0.0, double(cells - 1))); };
      // One cluster per facing within a cell: vertices of surfaces that face apart never
      // merge, so no triangle folds over between them or stands across the gap.
      key = (std::uint64_t(axisOf[v]) << 60) | (c(q.x) << 40) | (c(q.y) << 20) | c(q.z);
    }
    auto [it, fresh] = cellIndex.try_emplace(key, std::uint32_t(sum.size()));
    if (fresh) sum.emplace_back(0.0), count.push_back(0);
    cellOf[v] = it->second;
    sum[it->second] += shape.positions[v];
    ++count[it->second];
  }
  std::vector<std::uint32_t> rep(sum.size(), 0xffffffffu);
  std::vector<double> repDist(sum.size(), std::numeric_limits<double>::max());
  for (std::uint32_t v : indices) {
    const std::uint32_t c = cellOf[v];
    const double d = glm::length(shape.positions[v] - sum[c] / double(count[c]));
    if (d < repDist[c] || (d == repDist[c] && v < rep[c])) repDist[c] = d, rep[c] = v;
  }
  Simplifier::ReducedShape out;
  std::unordered_map<std::uint64_t, bool> seen;  // triangles as sorted cell triples
  for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
    std::uint32_t c[3] = {cellOf[indices[i]], cellOf[indices[i + 1]], cellOf[indices[i + 2]]};
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
    // A triangle that clustering turned over (its representatives wound against the triangle it
    // came from) would face away from its surface: culled, a hole; seen from behind, a shard.
    // It is wound back (dropping it could take a cut vertex's last triangle).
    const glm::dvec3& p0 = shape.positions[indices[i]];
    const glm::dvec3 before =
        glm::cross(shape.positions[indices[i + 1]] - p0, shape.positions[indices[i + 2]] - p0);
    const glm::dvec3& r0 = shape.positions[rep[c[0]]];
    const glm::dvec3 after =
        glm::cross(shape.positions[rep[c[1]]] - r0, shape.positions[rep[c[2]]] - r0);
    const bool turned = !(glm::dot(before, after) > 0.0);
    std::uint32_t s[3] = {c[0], c[1], c[2]};
    std::sort(s, s + 3);
    const std::uint64_t key = (std::uint64_t(s[0]) << 42) ^ (std::uint64_t(s[1]) << 21) ^ s[2];
    if (!seen.try_emplace(key, true).second) continue;
    if (turned)  // wound back to face as the triangle it came from
      out.indices.insert(out.indices.end(), {rep[c[0]], rep[c[2]], rep[c[1]]});
    else
      out.indices.insert(out.indices.end(), {rep[c[0]], rep[c[1]], rep[c[2]]});
  }
  for (std::uint32_t v : indices)
    out.geometricError = std::max(
        out.geometricError, glm::length(shape.positions[v] - shape.positions[rep[cellOf[v]]]));
  return out;
}

}  // namespace

// Vertex clustering (as meshopt_simplifySloppy, but keeping locked vertices): the finest grid
// whose result has at most targetTriangles triangles, found by bisection on the grid size.
Simplifier::ReducedShape clusterVertices(const Simplifier::Shape& shape,
                                         const std::vector<std::uint32_t>& indices,
                                         std::size_t targetTriangles) {
  const std::vector<std::uint8_t> axisOf = facingAxis(shape, indices);
  int lo = 1, hi = 1 << 20;
  Simplifier::ReducedShape best = clusterOnGrid(shape, indices, axisOf, lo);
  while (hi - lo > 1) {
    const int mid = lo + (hi - lo) / 2;
    Simplifier::ReducedShape r = clusterOnGrid(shape, indices, axisOf, mid);
    if (r.indices.size() / 3 <= targetTriangles) {
      lo = mid;
      best = std::move(r);
    } else {
      hi = mid;
    }
  }
  return best;
}

}  // namespace hlod
