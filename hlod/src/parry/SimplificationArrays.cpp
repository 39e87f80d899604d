// Parry et al. sec. 5: the simplification arrays (vertices, triangles, increments, references).
#include "hlod/parry/SimplificationArrays.h"

#include <algorithm>
#include <cassert>
#include <numeric>
#include <utility>

namespace hlod {

namespace {

// The internal nodes in the order they combine: the forest's smallest splat size first, then the
// corner merges in the order they were made. A parent's sphere holds its children's, so its
// radius is never smaller; on equal radii the lower index (children are made before their
// parents) goes first.
std::vector<std::uint32_t> combinationOrder(const SphereHierarchy& h) {
  std::vector<std::uint32_t> order;
  for (std::uint32_t n = std::uint32_t(h.leafCount); n < h.nodes.size(); ++n) order.push_back(n);
  const auto forestEnd = order.end() - std::ptrdiff_t(h.merges);
  std::sort(order.begin(), forestEnd, [&](std::uint32_t a, std::uint32_t b) {
    return h.nodes[a].radius != h.nodes[b].radius ? h.nodes[a].radius < h.nodes[b].radius : a < b;
  });
  return order;
}

// Sphere references: each node points at the node it was combined into (itself while it stands).
struct References {
  std::vector<std::uint32_t> to;
  explicit References(std::size_t n) : to(n) { std::iota(to.begin(), to.end(), 0u); }
  std::uint32_t find(std::uint32_t v) {
    std::uint32_t r = v;
    while (to[r] != r) r = to[r];
    while (to[v] != r) v = std::exchange(to[v], r);
    return r;
  }
};

}  // namespace

std::size_t SimplificationArrays::minTriangles() const {
  const std::size_t decimated =
      std::accumulate(increments.begin(), increments.end(), std::size_t(0));
  return triangleCount() - decimated;
}

SimplificationArrays buildSimplificationArrays(const SphereHierarchy& hierarchy,
                                               std::span<const std::uint32_t> indices) {
  const std::size_t nodeCount = hierarchy.nodes.size();
  SimplificationArrays a;
  // The live triangles at each standing sphere (a triangle is listed at each of its corners').
  std::vector<std::vector<std::uint32_t>> incident(nodeCount);
  std::vector<std::uint32_t> kept;    // the triangles considered, three leaves each
  std::vector<std::uint32_t> keptId;  // their index in indices
  for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
    const std::uint32_t t[3] = {indices[i], indices[i + 1], indices[i + 2]};
    assert(t[0] < hierarchy.leafCount && t[1] < hierarchy.leafCount && t[2] < hierarchy.leafCount);
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    const auto id = std::uint32_t(kept.size() / 3);
    kept.insert(kept.end(), t, t + 3);
    keptId.push_back(std::uint32_t(i / 3));
    for (std::uint32_t v : t) incident[v].push_back(id);
  }
  std::vector<std::uint8_t> live(kept.size() / 3, 1);
  References refs(nodeCount);
  for (std::uint32_t p : combinationOrder(hierarchy)) {
    const std::uint32_t c0 = hierarchy.nodes[p].child[0], c1 = hierarchy.nodes[p].child[1];
    assert(refs.find(c0) == c0 && refs.find(c1) == c1);  // children combine before parents
    // The smaller list is scanned for triangles that have the other child too: decimated.
    const bool firstSmaller = incident[c0].size() <= incident[c1].size();
    std::vector<std::uint32_t>& small = incident[firstSmaller ? c0 : c1];
    std::vector<std::uint32_t>& large = incident[firstSmaller ? c1 : c0];
    const std::uint32_t other = firstSmaller ? c1 : c0;
    std::uint32_t decimated = 0;
    for (std::uint32_t t : small) {
      if (!live[t]) continue;
      bool both = false;
      for (int k = 0; k < 3; ++k) both = both || refs.find(kept[3 * t + k]) == other;
      if (!both) continue;
      live[t] = 0;
      a.triangles.insert(a.triangles.end(), &kept[3 * t], &kept[3 * t + 3]);
      a.triangleIds.push_back(keptId[t]);
      ++decimated;
    }
    // The parent takes the live triangles of both (lists merged small into large).
    std::vector<std::uint32_t> merged = std::move(large);
    std::erase_if(merged, [&](std::uint32_t t) { return !live[t]; });
    for (std::uint32_t t : small)
      if (live[t]) merged.push_back(t);
    small = {};
    incident[p] = std::move(merged);
    refs.to[c0] = p;
    refs.to[c1] = p;
    a.vertices.insert(a.vertices.end(), {c0, c1});
    a.increments.push_back(decimated);
  }
  for (std::size_t t = 0; t < live.size(); ++t)
    if (live[t]) {
      a.triangles.insert(a.triangles.end(), &kept[3 * t], &kept[3 * t + 3]);
      a.triangleIds.push_back(keptId[t]);
    }
  a.references.resize(hierarchy.leafCount);
  for (std::uint32_t v = 0; v < hierarchy.leafCount; ++v) a.references[v] = refs.find(v);
  return a;
}

Progression progressionOf(const SphereHierarchy& hierarchy, const SimplificationArrays& arrays) {
  Progression p;
  p.increments = arrays.increments;
  for (std::size_t j = 0; j < arrays.increments.size(); ++j) {
    const std::uint32_t c0 = arrays.vertices[2 * j], c1 = arrays.vertices[2 * j + 1];
    const std::uint32_t parent = hierarchy.nodes[c0].parent;
    p.moves.insert(p.moves.end(), {c0, parent, c1, parent});
    p.moveEnd.push_back(std::uint32_t(p.moves.size() / 2));
  }
  return p;
}

ProgressiveCut cutArrays(const SphereHierarchy& hierarchy, const SimplificationArrays& arrays,
                         std::size_t n) {
  const std::size_t triangles = arrays.triangleCount();
  n = std::clamp(n, arrays.minTriangles(), triangles);
  const std::size_t start = triangles - n;
  // Combinations made: those whose decimated triangles all lie before the last n.
  References refs(hierarchy.nodes.size());
  std::size_t made = 0, first = 0;  // first: the first triangle kept
  ProgressiveCut cut;
  // Made: every combination before the boundary between combinations nearest the cut (a
  // combination of two clusters may decimate many triangles at once).
  while (made < arrays.increments.size() && first < start &&
         (first + arrays.increments[made] <= start ||
          first + arrays.increments[made] - start <= start - first)) {
    const std::uint32_t c0 = arrays.vertices[2 * made], c1 = arrays.vertices[2 * made + 1];
    const std::uint32_t p = hierarchy.nodes[c0].parent;
    refs.to[c0] = p;
    refs.to[c1] = p;
    cut.splatSize = hierarchy.nodes[p].radius;
    first += arrays.increments[made++];
  }
  // The cut's vertices: the corners of its triangles, then the spheres of the combinations left.
  std::vector<std::uint32_t> local(hierarchy.nodes.size(), kNoSphere);
  const auto number = [&](std::uint32_t sphere) {
    if (local[sphere] == kNoSphere) {
      local[sphere] = std::uint32_t(cut.vertices.size());
      cut.vertices.push_back(sphere);
    }
    return local[sphere];
  };
  for (std::size_t i = 3 * first; i < arrays.triangles.size(); ++i)
    cut.indices.push_back(number(refs.find(arrays.triangles[i])));
  cut.triangleIds.assign(arrays.triangleIds.begin() + std::ptrdiff_t(first),
                         arrays.triangleIds.end());
  for (std::size_t j = made; j < arrays.increments.size(); ++j) {
    const std::uint32_t c0 = arrays.vertices[2 * j], c1 = arrays.vertices[2 * j + 1];
    const std::uint32_t parent = number(hierarchy.nodes[c0].parent);
    cut.progression.moves.insert(cut.progression.moves.end(),
                                 {number(c0), parent, number(c1), parent});
    cut.progression.moveEnd.push_back(std::uint32_t(cut.progression.moves.size() / 2));
    cut.progression.increments.push_back(arrays.increments[j]);
  }
  return cut;
}

}  // namespace hlod
