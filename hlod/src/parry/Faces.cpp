// Parry et al. sec. 3-4: a block's facades and near-planar faces.
#include "hlod/parry/Faces.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

namespace hlod {

namespace {

// Per triangle, the triangles that share one of its edges (the same two vertex indices).
std::vector<std::vector<std::uint32_t>> edgeNeighbours(const Mesh& mesh) {
  const std::size_t n = mesh.triangleCount();
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;
  edges.reserve(3 * n);
  for (std::uint32_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = mesh.indices[3 * t + k], b = mesh.indices[3 * t + (k + 1) % 3];
      edges.emplace_back((std::uint64_t(std::min(a, b)) << 32) | std::max(a, b), t);
    }
  std::sort(edges.begin(), edges.end());
  std::vector<std::vector<std::uint32_t>> out(n);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    for (std::size_t x = i; x < j; ++x)
      for (std::size_t y = i; y < j; ++y)
        if (edges[x].second != edges[y].second) out[edges[x].second].push_back(edges[y].second);
    i = j;
  }
  return out;
}

}  // namespace

FaceSegmentation segmentFaces(const Mesh& mesh, const FaceParams& params) {
  const std::size_t n = mesh.triangleCount();
  FaceSegmentation seg;
  seg.faceOf.assign(n, 0xffffffffu);
  std::vector<glm::dvec3> normal(n);
  std::vector<double> area(n);
  for (std::size_t t = 0; t < n; ++t) {
    const glm::dvec3& a = mesh.positions[mesh.indices[3 * t]];
    const glm::dvec3 c = glm::cross(mesh.positions[mesh.indices[3 * t + 1]] - a,
                                    mesh.positions[mesh.indices[3 * t + 2]] - a);
    const double len = glm::length(c);
    area[t] = 0.5 * len;
    normal[t] = len > 0.0 && std::isfinite(len) ? c / len : glm::dvec3(0.0);
  }
  const auto neighbours = edgeNeighbours(mesh);
  const double tolerance = params.planeTolerance * glm::length(mesh.bounds().size());
  const double minCos = std::cos(params.maxAngleDegrees * M_PI / 180.0);
  std::vector<std::uint32_t> seeds(n);
  std::iota(seeds.begin(), seeds.end(), 0u);
  std::stable_sort(seeds.begin(), seeds.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return area[a] > area[b]; });
  std::vector<std::uint32_t> queue;
  for (std::uint32_t seed : seeds) {
    if (seg.faceOf[seed] != 0xffffffffu) continue;
    const auto id = std::uint32_t(seg.faces.size());
    Face face;
    face.normal = glm::dot(normal[seed], normal[seed]) > 0.0 ? normal[seed] : glm::dvec3(0, 0, 1);
    const double offset = glm::dot(face.normal, mesh.positions[mesh.indices[3 * seed]]);
    // A triangle of no area says nothing of the plane: it joins whatever face reaches it.
    const bool flatSeed = area[seed] > 0.0;
    const auto fits = [&](std::uint32_t t) {
      if (!flatSeed) return area[t] == 0.0;
      if (area[t] > 0.0 && glm::dot(normal[t], face.normal) < minCos) return false;
      for (int k = 0; k < 3; ++k)
        if (std::abs(glm::dot(face.normal, mesh.positions[mesh.indices[3 * t + k]]) - offset) >
            tolerance)
          return false;
      return true;
    };
    queue.assign(1, seed);
    seg.faceOf[seed] = id;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const std::uint32_t t = queue[head];
      face.area += area[t];
      ++face.triangles;
      for (std::uint32_t u : neighbours[t])
        if (seg.faceOf[u] == 0xffffffffu && fits(u)) {
          seg.faceOf[u] = id;
          queue.push_back(u);
        }
    }
    seg.faces.push_back(face);
  }
  return seg;
}

namespace {

// The facade of a face by its normal alone.
std::vector<std::uint32_t> facadesByNormal(const FaceSegmentation& seg, UpAxis up) {
  const int u = int(up), e = (u + 1) % 3, f = (u + 2) % 3;
  const double cos45 = std::sqrt(0.5);
  // The dominant direction modulo 90 degrees: the area-weighted mean of 4 * azimuth.
  double c4 = 0.0, s4 = 0.0;
  for (const Face& face : seg.faces) {
    const double h = std::hypot(face.normal[e], face.normal[f]);
    if (h <= 0.0 || std::abs(face.normal[u]) > cos45) continue;
    const double azimuth = std::atan2(face.normal[f], face.normal[e]);
    c4 += face.area * std::cos(4.0 * azimuth);
    s4 += face.area * std::sin(4.0 * azimuth);
  }
  const double dominant = std::atan2(s4, c4) / 4.0;
  std::vector<std::uint32_t> out(seg.faces.size());
  for (std::size_t i = 0; i < seg.faces.size(); ++i) {
    const glm::dvec3& n = seg.faces[i].normal;
    if (n[u] > cos45) {
      out[i] = kFacadeRoof;
    } else if (n[u] < -cos45) {
      out[i] = kFacadeUnderside;
    } else {
      const double turns = (std::atan2(n[f], n[e]) - dominant) / (M_PI / 2.0);
      const long side = std::lround(turns);
      out[i] = std::uint32_t(((side % long(kFacadeSides)) + long(kFacadeSides)) % kFacadeSides);
    }
  }
  return out;
}

struct PositionKeyHash {
  std::size_t operator()(const glm::dvec3& p) const {
    const std::hash<double> h;
    return h(p.x) ^ (h(p.y) * 31) ^ (h(p.z) * 1009);
  }
};

}  // namespace

std::vector<std::uint32_t> facadesOf(const Mesh& mesh, const FaceSegmentation& seg, UpAxis up) {
  std::vector<std::uint32_t> facade = facadesByNormal(seg, up);
  std::vector<double> facadeArea(kFacadeCount, 0.0);
  for (std::size_t f = 0; f < seg.faces.size(); ++f) facadeArea[facade[f]] += seg.faces[f].area;
  // Outline shared by two faces, by position (a texture seam between them has two vertices).
  std::unordered_map<glm::dvec3, std::uint32_t, PositionKeyHash> id;
  const auto positionId = [&](std::uint32_t v) {
    return id.try_emplace(mesh.positions[v] + glm::dvec3(0.0), std::uint32_t(id.size()))
        .first->second;
  };
  std::map<std::uint64_t, std::vector<std::uint32_t>> edgeFaces;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = positionId(mesh.indices[3 * t + k]);
      const std::uint32_t b = positionId(mesh.indices[3 * t + (k + 1) % 3]);
      edgeFaces[(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b)].push_back(seg.faceOf[t]);
    }
  std::vector<glm::dvec3> at(id.size());
  for (const auto& [p, i] : id) at[i] = p;
  std::map<std::pair<std::uint32_t, std::uint32_t>, double> shared;  // (face, neighbour) -> length
  for (const auto& [key, faces] : edgeFaces) {
    const double length = glm::length(at[key >> 32] - at[key & 0xffffffffu]);
    for (std::uint32_t f : faces)
      for (std::uint32_t g : faces)
        if (f != g) shared[{f, g}] += length;
  }
  std::vector<std::uint32_t> details;
  for (std::uint32_t f = 0; f < seg.faces.size(); ++f)
    if (seg.faces[f].area < kDetailShare * facadeArea[facade[f]]) details.push_back(f);
  std::stable_sort(details.begin(), details.end(), [&](std::uint32_t a, std::uint32_t b) {
    return seg.faces[a].area > seg.faces[b].area;
  });
  std::vector<std::uint8_t> detail(seg.faces.size(), 0);
  for (std::uint32_t f : details) detail[f] = 1;
  for (std::uint32_t f : details) {
    double best = 0.0;
    for (auto it = shared.lower_bound({f, 0}); it != shared.end() && it->first.first == f; ++it) {
      const std::uint32_t g = it->first.second;
      if (!detail[g] && it->second > best) best = it->second, facade[f] = facade[g];
    }
    if (best > 0.0) detail[f] = 0;  // placed: its own details may follow it
  }
  return facade;
}

}  // namespace hlod
