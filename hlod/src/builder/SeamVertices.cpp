#include "hlod/builder/SeamVertices.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

namespace hlod {

namespace {

bool lessOn(int first, const glm::dvec3& a, const glm::dvec3& b) {
  const int second = (first + 1) % 3, third = (first + 2) % 3;
  return std::tie(a[first], a[second], a[third]) < std::tie(b[first], b[second], b[third]);
}

}  // namespace

void SeamVertices::sortPlane(const CutPlane& plane, OnPlane& v) {
  const int u = (plane.axis + 1) % 3, w = (plane.axis + 2) % 3;
  auto byU = [u](const glm::dvec3& a, const glm::dvec3& b) { return lessOn(u, a, b); };
  std::sort(v.byU.begin(), v.byU.end(), byU);
  v.byU.erase(std::unique(v.byU.begin(), v.byU.end()), v.byU.end());
  v.byV = v.byU;
  std::sort(v.byV.begin(), v.byV.end(),
            [w](const glm::dvec3& a, const glm::dvec3& b) { return lessOn(w, a, b); });
}

void SeamVertices::collect(const Mesh& mesh, std::span<const CutPlane> planes) {
  std::set<CutPlane> touched;
  for (const auto& p : mesh.positions) {
    for (const CutPlane& plane : planes) {
      if (!plane.contains(p)) continue;
      planes_[plane].byU.push_back(p + glm::dvec3(0.0));  // -0.0 as 0.0
      touched.insert(plane);
    }
  }
  for (const CutPlane& plane : touched) sortPlane(plane, planes_[plane]);
}

void SeamVertices::merge(const SeamVertices& other) {
  for (const auto& [plane, v] : other.planes_) {
    OnPlane& mine = planes_[plane];
    mine.byU.insert(mine.byU.end(), v.byU.begin(), v.byU.end());
    sortPlane(plane, mine);
  }
}

std::size_t SeamVertices::size() const {
  std::size_t n = 0;
  for (const auto& [plane, v] : planes_) n += v.byU.size();
  return n;
}

void SeamVertices::verticesOnSegment(const CutPlane& plane, const glm::dvec3& a,
                                     const glm::dvec3& b,
                                     std::vector<std::pair<double, glm::dvec3>>& out) const {
  out.clear();
  auto it = planes_.find(plane);
  if (it == planes_.end()) return;
  const int u = (plane.axis + 1) % 3, w = (plane.axis + 2) % 3;
  // Search along the in-plane axis on which the segment is longer.
  const bool alongU = std::abs(b[u] - a[u]) >= std::abs(b[w] - a[w]);
  const int c = alongU ? u : w, o = alongU ? w : u;
  const std::vector<glm::dvec3>& sorted = alongU ? it->second.byU : it->second.byV;
  const double lo = std::min(a[c], b[c]), hi = std::max(a[c], b[c]);
  if (!(hi > lo)) return;
  auto first = std::lower_bound(sorted.begin(), sorted.end(), lo,
                                [c](const glm::dvec3& p, double x) { return p[c] < x; });
  const double length = glm::length(b - a);
  // A recorded vertex was cut from this very edge, so it lies on it up to rounding.
  const double tolerance =
      1e-9 * length + 1e-14 * std::max({std::abs(a[o]), std::abs(b[o]), std::abs(a[c])});
  for (auto p = first; p != sorted.end() && (*p)[c] <= hi; ++p) {
    const double t = ((*p)[c] - a[c]) / (b[c] - a[c]);
    if (!(t > 0.0 && t < 1.0)) continue;
    const double expected = a[o] + t * (b[o] - a[o]);
    if (std::abs((*p)[o] - expected) > tolerance) continue;
    if (*p == a || *p == b) continue;
    out.emplace_back(t, *p);
  }
  std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
}

std::size_t SeamVertices::insertInto(Mesh& mesh, std::span<const CutPlane> planes) const {
  if (planes_.empty() || planes.empty()) return 0;
  const std::size_t nv0 = mesh.positions.size();
  const bool hasN = mesh.normals.size() == nv0;
  const bool hasUv = mesh.texCoords.size() == nv0;
  // The plane an edge lies in, if any.
  auto planeOf = [&](const glm::dvec3& a, const glm::dvec3& b) -> const CutPlane* {
    for (const CutPlane& plane : planes)
      if (plane.contains(a) && plane.contains(b) && planes_.count(plane)) return &plane;
    return nullptr;
  };
  // One new vertex per (edge, position), so triangles sharing an edge share its new vertices.
  std::map<std::tuple<std::uint32_t, std::uint32_t, double>, std::uint32_t> made;
  auto vertexOn = [&](std::uint32_t a, std::uint32_t b, double t, const glm::dvec3& p) {
    const std::uint32_t lo = std::min(a, b), hi = std::max(a, b);
    const double tLo = a == lo ? t : 1.0 - t;
    auto [it, fresh] = made.try_emplace({lo, hi, tLo}, 0u);
    if (!fresh) return it->second;
    it->second = std::uint32_t(mesh.positions.size());
    mesh.positions.push_back(p);
    if (hasN) {
      mesh.normals.push_back(
          normalizedOr(glm::mix(mesh.normals[a], mesh.normals[b], float(t)), mesh.normals[a]));
    }
    if (hasUv) mesh.texCoords.push_back(glm::mix(mesh.texCoords[a], mesh.texCoords[b], float(t)));
    return it->second;
  };
  std::vector<std::uint32_t> indices;
  indices.reserve(mesh.indices.size());
  std::vector<std::pair<double, glm::dvec3>> found;
  std::vector<std::uint32_t> edgePoints[3];
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const std::uint32_t v[3] = {mesh.indices[i], mesh.indices[i + 1], mesh.indices[i + 2]};
    bool split = false;
    for (int e = 0; e < 3; ++e) {
      edgePoints[e].clear();
      const std::uint32_t a = v[e], b = v[(e + 1) % 3];
      const CutPlane* plane = planeOf(mesh.positions[a], mesh.positions[b]);
      if (!plane) continue;
      verticesOnSegment(*plane, mesh.positions[a], mesh.positions[b], found);
      for (const auto& [t, p] : found) edgePoints[e].push_back(vertexOn(a, b, t, p));
      split = split || !edgePoints[e].empty();
    }
    if (!split) {
      indices.insert(indices.end(), {v[0], v[1], v[2]});
      continue;
    }
    // The triangle's boundary, corners and inserted vertices in winding order.
    std::vector<std::uint32_t> ring;
    for (int e = 0; e < 3; ++e) {
      ring.push_back(v[e]);
      ring.insert(ring.end(), edgePoints[e].begin(), edgePoints[e].end());
    }
    int apex = -1;  // a corner whose two edges have no new vertex: fan from there
    for (int k = 0; k < 3; ++k)
      if (edgePoints[k].empty() && edgePoints[(k + 2) % 3].empty()) apex = k;
    const glm::dvec3 p0 = mesh.positions[v[0]], p1 = mesh.positions[v[1]],
                     p2 = mesh.positions[v[2]];
    const double longest =
        std::max({glm::length(p1 - p0), glm::length(p2 - p1), glm::length(p0 - p2)});
    const bool sliver = !(glm::length(glm::cross(p1 - p0, p2 - p0)) > 1e-9 * longest * longest);
    if (apex < 0 && !sliver) {
      // A fan around a new centre vertex.
      const auto c = std::uint32_t(mesh.positions.size());
      mesh.positions.push_back((p0 + p1 + p2) / 3.0);
      if (hasN) {
        mesh.normals.push_back(normalizedOr(
            mesh.normals[v[0]] + mesh.normals[v[1]] + mesh.normals[v[2]], mesh.normals[v[0]]));
      }
      if (hasUv)
        mesh.texCoords.push_back(
            (mesh.texCoords[v[0]] + mesh.texCoords[v[1]] + mesh.texCoords[v[2]]) / 3.0f);
      for (std::size_t k = 0; k < ring.size(); ++k)
        indices.insert(indices.end(), {c, ring[k], ring[(k + 1) % ring.size()]});
      continue;
    }
    // A sliver (cuts through the line where two planes meet make them) would put its centre on
    // or beside its own edges: fan from a corner; the triangles over points on the corner's own
    // edges have zero area.
    if (apex < 0) apex = 0;
    std::rotate(ring.begin(), std::find(ring.begin(), ring.end(), v[apex]), ring.end());
    for (std::size_t k = 1; k + 1 < ring.size(); ++k)
      indices.insert(indices.end(), {ring[0], ring[k], ring[k + 1]});
  }
  mesh.indices = std::move(indices);
  return mesh.positions.size() - nv0;
}

}  // namespace hlod
