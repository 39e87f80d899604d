#include "builder/SlabPartition.h"

#include <algorithm>
#include <cassert>
#include <limits>

namespace hlod {

int longestAxis(const Aabb& box) {
  const glm::dvec3 s = box.size();
  if (s.y > s.x && s.y >= s.z) return 1;
  if (s.z > s.x && s.z > s.y) return 2;
  return 0;
}

glm::dvec3 centroid(const Mesh& mesh, std::size_t t) {
  return (mesh.positions[mesh.indices[t * 3]] + mesh.positions[mesh.indices[t * 3 + 1]] +
          mesh.positions[mesh.indices[t * 3 + 2]]) /
         3.0;
}

namespace {

struct Centroids {
  std::vector<glm::dvec3> at;
  int axis = 0;  // their longest extent
  double lo = 0.0, hi = 0.0;
};

Centroids centroidsOf(const Mesh& mesh) {
  Centroids c;
  c.at.resize(mesh.triangleCount());
  Aabb box;
  for (std::size_t t = 0; t < c.at.size(); ++t) box.extend(c.at[t] = centroid(mesh, t));
  c.axis = longestAxis(box);
  c.lo = box.min[c.axis];
  c.hi = box.max[c.axis];
  return c;
}

// Each triangle to the slab of its centroid (on a plane: the slab below).
SlabPartition assign(const Centroids& c, std::vector<double> planes) {
  SlabPartition out;
  out.axis = c.axis;
  out.planes = std::move(planes);
  out.triangles.resize(out.planes.size() + 1);
  for (std::size_t t = 0; t < c.at.size(); ++t) {
    const auto slab =
        std::size_t(std::lower_bound(out.planes.begin(), out.planes.end(), c.at[t][c.axis]) -
                    out.planes.begin());
    out.triangles[slab].push_back(std::uint32_t(t));
  }
  return out;
}

}  // namespace

SlabPartition partitionIntoSlabs(const Mesh& mesh, int levelFactor) {
  assert(levelFactor >= 2);
  const Centroids c = centroidsOf(mesh);
  std::vector<double> planes;
  for (int k = 1; k < levelFactor; ++k)
    planes.push_back(c.lo + (c.hi - c.lo) * double(k) / double(levelFactor));
  return assign(c, std::move(planes));
}

SlabPartition partitionByCount(const Mesh& mesh, int levelFactor) {
  assert(levelFactor >= 2);
  const Centroids c = centroidsOf(mesh);
  std::vector<double> along(c.at.size());
  for (std::size_t t = 0; t < along.size(); ++t) along[t] = c.at[t][c.axis];
  std::sort(along.begin(), along.end());
  std::vector<double> planes;
  for (int k = 1; k < levelFactor; ++k) {
    const double plane = along[along.size() * std::size_t(k) / std::size_t(levelFactor) - 1];
    if (planes.empty() || plane > planes.back()) planes.push_back(plane);
  }
  SlabPartition out = assign(c, std::move(planes));
  mergeSmallSlabs(out, 1);  // ties at the top can leave the last slab empty
  return out;
}

void mergeSmallSlabs(SlabPartition& p, std::size_t minTriangles) {
  assert(p.planes.size() + 1 == p.triangles.size());
  while (p.triangles.size() > 1) {
    std::size_t k = p.triangles.size();
    for (std::size_t i = 0; i < p.triangles.size(); ++i)
      if (p.triangles[i].size() < minTriangles &&
          (k == p.triangles.size() || p.triangles[i].size() < p.triangles[k].size()))
        k = i;
    if (k == p.triangles.size()) return;
    // Into the smaller neighbour: slab j = k - 1 or k + 1, then j and j + 1 become one.
    const bool left = k > 0 && (k + 1 == p.triangles.size() ||
                                p.triangles[k - 1].size() <= p.triangles[k + 1].size());
    const std::size_t j = left ? k - 1 : k;
    auto& into = p.triangles[j];
    into.insert(into.end(), p.triangles[j + 1].begin(), p.triangles[j + 1].end());
    p.triangles.erase(p.triangles.begin() + std::ptrdiff_t(j) + 1);
    p.planes.erase(p.planes.begin() + std::ptrdiff_t(j));
  }
}

Mesh subMesh(const Mesh& mesh, std::span<const std::uint32_t> triangles,
             std::vector<std::uint32_t>* origin) {
  constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  Mesh out;
  out.name = mesh.name;
  out.baseColor = mesh.baseColor;
  out.texture = mesh.texture;
  out.oneSided = mesh.oneSided;
  const std::size_t nv = mesh.positions.size();
  const bool hasN = mesh.normals.size() == nv, hasUv = mesh.texCoords.size() == nv;
  std::vector<std::uint32_t> remap(nv, kUnused);
  if (origin) origin->clear();
  out.indices.reserve(triangles.size() * 3);
  for (std::uint32_t t : triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.indices[std::size_t(t) * 3 + k];
      if (remap[v] == kUnused) {
        remap[v] = std::uint32_t(out.positions.size());
        out.positions.push_back(mesh.positions[v]);
        if (hasN) out.normals.push_back(mesh.normals[v]);
        if (hasUv) out.texCoords.push_back(mesh.texCoords[v]);
        if (origin) origin->push_back(v);
      }
      out.indices.push_back(remap[v]);
    }
  return out;
}

void halveUntilSmall(const std::vector<glm::dvec3>& centroids, std::vector<std::uint32_t> triangles,
                     std::size_t maxTriangles, int depth,
                     std::vector<std::vector<std::uint32_t>>& out) {
  Aabb box;
  for (std::uint32_t t : triangles) box.extend(centroids[t]);
  const int axis = longestAxis(box);
  if (triangles.size() <= maxTriangles || depth >= 48 || !(box.size()[axis] > 0.0)) {
    out.push_back(std::move(triangles));
    return;
  }
  const double mid = box.centre()[axis];
  std::vector<std::uint32_t> below, above;
  for (std::uint32_t t : triangles) (centroids[t][axis] <= mid ? below : above).push_back(t);
  triangles = {};
  halveUntilSmall(centroids, std::move(below), maxTriangles, depth + 1, out);
  halveUntilSmall(centroids, std::move(above), maxTriangles, depth + 1, out);
}

SlabPartition divideIntoSlabs(const Mesh& piece, int levelFactor, std::size_t minLeafTri) {
  SlabPartition slabs = partitionIntoSlabs(piece, levelFactor);
  mergeSmallSlabs(slabs, minLeafTri);
  // One slab left: the triangles bunch up in one slab; divide them by count instead.
  if (slabs.triangles.size() < 2) slabs = partitionByCount(piece, levelFactor);
  return slabs;
}

}  // namespace hlod
