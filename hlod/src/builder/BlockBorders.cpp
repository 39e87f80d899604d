// Lock flags from a block's borders, its seam and its sides (builder/BlockBorders.h).
#include "builder/BlockBorders.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "builder/SimplifierImpl.h"

namespace hlod {

BlockBorders blockBorders(const Mesh& block, std::span<const glm::dvec3> seam) {
  BlockBorders b;
  std::unordered_map<glm::dvec3, std::uint32_t, PositionHash> id;
  b.positionOf.resize(block.positions.size());
  for (std::size_t v = 0; v < block.positions.size(); ++v)
    b.positionOf[v] = id.try_emplace(block.positions[v] + glm::dvec3(0.0), std::uint32_t(id.size()))
                          .first->second;
  b.corners.assign(id.size(), 0);
  b.seam.assign(id.size(), 0);
  b.scratch.assign(id.size(), 0);
  for (std::uint32_t v : block.indices) ++b.corners[b.positionOf[v]];
  for (const glm::dvec3& p : seam)
    if (auto it = id.find(p + glm::dvec3(0.0)); it != id.end()) b.seam[it->second] = 1;
  return b;
}

std::vector<std::uint8_t> lockBorder(const Mesh& piece, const std::vector<std::uint32_t>& origin,
                                     BlockBorders& b) {
  for (std::uint32_t v : piece.indices) ++b.scratch[b.positionOf[origin[v]]];
  std::vector<std::uint8_t> locked(piece.positions.size(), 0);
  for (std::size_t v = 0; v < piece.positions.size(); ++v) {
    const std::uint32_t p = b.positionOf[origin[v]];
    if (b.seam[p] || b.scratch[p] < b.corners[p]) locked[v] = kVertexLocked;
  }
  for (std::uint32_t v : piece.indices) b.scratch[b.positionOf[origin[v]]] = 0;
  return locked;
}

void markOutline(const Mesh& piece, const std::vector<std::uint32_t>& origin, BlockBorders& b,
                 std::span<const CutPlane> sides, std::vector<std::uint8_t>& flags) {
  if (sides.empty()) return;
  // The piece's positions, numbered in the order they first appear (the block's position ids,
  // through b.scratch, which is zero again on return).
  std::vector<glm::dvec3> at;
  std::vector<std::uint32_t> idOf(piece.positions.size());
  for (std::size_t v = 0; v < piece.positions.size(); ++v) {
    std::uint32_t& local = b.scratch[b.positionOf[origin[v]]];
    if (local == 0) {
      at.push_back(piece.positions[v]);
      local = std::uint32_t(at.size());
    }
    idOf[v] = local - 1;
  }
  for (std::size_t v = 0; v < piece.positions.size(); ++v) b.scratch[b.positionOf[origin[v]]] = 0;
  // An edge used once lies on the open border: the edges sorted, an edge's uses in a run.
  std::vector<std::uint64_t> edges;
  edges.reserve(piece.indices.size());
  for (std::size_t i = 0; i + 2 < piece.indices.size(); i += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t p = idOf[piece.indices[i + k]], q = idOf[piece.indices[i + (k + 1) % 3]];
      if (p != q) edges.push_back((std::uint64_t(std::min(p, q)) << 32) | std::max(p, q));
    }
  std::sort(edges.begin(), edges.end());
  std::vector<std::vector<std::uint32_t>> borderNeighbours(at.size());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t end = i + 1;
    while (end < edges.size() && edges[end] == edges[i]) ++end;
    if (end - i == 1) {
      const auto p = std::uint32_t(edges[i] >> 32), q = std::uint32_t(edges[i] & 0xffffffffu);
      borderNeighbours[p].push_back(q);
      borderNeighbours[q].push_back(p);
    }
    i = end;
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

double errorLimit(double blockArea, std::size_t blockTriangles, double s) {
  return std::sqrt(blockArea * s / double(std::max<std::size_t>(1, blockTriangles)));
}

}  // namespace hlod
