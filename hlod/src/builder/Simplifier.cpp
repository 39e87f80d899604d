#include "hlod/builder/Simplifier.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>

#include "builder/SamePosition.h"
#include "builder/ShapeGuard.h"
#include "builder/SimplifierImpl.h"

namespace hlod {

Result<std::unique_ptr<Simplifier>> makeSimplifier(std::string_view name) {
  if (name == "meshopt") return std::unique_ptr<Simplifier>(makeMeshoptSimplifier());
  if (name == "openmesh") return std::unique_ptr<Simplifier>(makeOpenMeshSimplifier());
  if (name == "parry") return std::unique_ptr<Simplifier>(makeParrySimplifier());
  return makeError("unknown simplifier '" + std::string(name) +
                   "' (choose meshopt, openmesh or parry)");
}

namespace {

struct WeldKey {
  glm::dvec3 p;
  glm::vec2 uv;
  bool operator==(const WeldKey& o) const {
    return std::memcmp(&p, &o.p, sizeof p) == 0 && std::memcmp(&uv, &o.uv, sizeof uv) == 0;
  }
};

struct WeldKeyHash {
  std::size_t operator()(const WeldKey& k) const {
    // FNV-1a over the bytes: exact equality is what welding needs.
    unsigned char bytes[sizeof(glm::dvec3) + sizeof(glm::vec2)];
    std::memcpy(bytes, &k.p, sizeof k.p);
    std::memcpy(bytes + sizeof k.p, &k.uv, sizeof k.uv);
    std::uint64_t h = 1469598103934665603ull;
    for (unsigned char b : bytes) h = (h ^ b) * 1099511628211ull;
    return std::size_t(h);
  }
};

// A mesh with the material of `mesh` and no geometry.
Mesh emptyLike(const Mesh& mesh) {
  Mesh out;
  out.name = mesh.name;
  out.baseColor = mesh.baseColor;
  out.texture = mesh.texture;
  out.oneSided = mesh.oneSided;
  return out;
}

glm::dvec3 triangleNormal(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double len = glm::length(n);
  return len > 0.0 && std::isfinite(len) ? n / len : glm::dvec3(0.0);
}

}  // namespace

SimplifiedMesh Simplifier::simplify(const Mesh& mesh, std::size_t targetTriangles,
                                    const std::vector<std::uint8_t>& locked,
                                    double errorLimit) const {
  return simplifyShape(mesh, targetTriangles, locked, errorLimit, false);
}

SimplifiedMesh Simplifier::simplifyUnion(const Mesh& mesh, std::size_t targetTriangles,
                                         const std::vector<std::uint8_t>& locked,
                                         double errorLimit) const {
  return simplifyShape(mesh, targetTriangles, locked, errorLimit, true);
}

SimplifiedMesh Simplifier::simplifyShape(const Mesh& mesh, std::size_t targetTriangles,
                                         const std::vector<std::uint8_t>& locked, double errorLimit,
                                         bool clusterEveryRound) const {
  if (mesh.triangleCount() <= targetTriangles || mesh.positions.empty()) return {mesh};
  const std::size_t nv = mesh.positions.size();
  // Weld by position: posOf[v] is the position index of input vertex v.
  std::vector<std::uint32_t> posOf(nv);
  std::vector<glm::dvec3> uniquePos;
  std::vector<std::uint8_t> posLocked;
  {
    const std::vector<std::uint32_t> first = firstAtSamePosition(mesh.positions);
    for (std::size_t v = 0; v < nv; ++v) {
      if (first[v] == v) {
        posOf[v] = std::uint32_t(uniquePos.size());
        uniquePos.push_back(mesh.positions[v]);
        posLocked.push_back(0);
      } else {
        posOf[v] = posOf[first[v]];
      }
      if (v < locked.size() && locked[v] && posLocked[posOf[v]] != kVertexLocked)
        posLocked[posOf[v]] = locked[v];
    }
  }
  // Triangles on positions; cornerVertex[c] is the input vertex at corner c.
  std::vector<std::uint32_t> corners, cornerVertex;
  std::vector<glm::dvec3> vertexNormal(nv, glm::dvec3(0.0));
  const bool hasN = mesh.normals.size() == nv;
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const auto a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
    if (a >= nv || b >= nv || c >= nv) continue;
    const auto pa = posOf[a], pb = posOf[b], pc = posOf[c];
    if (pa == pb || pb == pc || pa == pc) continue;
    corners.insert(corners.end(), {pa, pb, pc});
    cornerVertex.insert(cornerVertex.end(), {a, b, c});
    if (!hasN) {
      // Each input vertex's normal: its own, or the area-weighted normal of its triangles.
      const glm::dvec3 n =
          glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
      if (std::isfinite(n.x + n.y + n.z)) {
        for (auto v : {a, b, c}) vertexNormal[v] += n;
      }
    }
  }
  for (std::size_t v = 0; v < nv; ++v) {
    const glm::dvec3 n = hasN ? glm::dvec3(mesh.normals[v]) : vertexNormal[v];
    const double len = glm::length(n);
    vertexNormal[v] = len > 0.0 && std::isfinite(len) ? n / len : glm::dvec3(0.0);
  }
  // Split non-manifold positions (a small box touching a wall at one corner, two roofs meeting at
  // an edge): corners around a position that are joined through edges shared by exactly two
  // triangles form one fan, and each fan becomes its own shape vertex. Edge collapses can then
  // remove the box; a non-manifold vertex would be frozen.
  const std::size_t nc = corners.size();
  std::vector<std::uint32_t> fanRoot(nc);
  std::iota(fanRoot.begin(), fanRoot.end(), 0u);
  auto root = [&](std::uint32_t x) {
    while (fanRoot[x] != x) x = fanRoot[x] = fanRoot[fanRoot[x]];
    return x;
  };
  {
    // Per undirected edge, the triangles using it (two common, more when non-manifold): the
    // (edge, triangle) pairs sorted, an edge's in a run.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;
    edges.reserve(nc);
    for (std::size_t t = 0; t < nc / 3; ++t)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t p = corners[3 * t + k], q = corners[3 * t + (k + 1) % 3];
        edges.emplace_back((std::uint64_t(std::min(p, q)) << 32) | std::max(p, q),
                           std::uint32_t(t));
      }
    std::sort(edges.begin(), edges.end());
    auto cornerOf = [&](std::uint32_t t, std::uint32_t p) {
      for (std::uint32_t k = 0; k < 3; ++k)
        if (corners[3 * t + k] == p) return 3 * t + k;
      return 3 * t;
    };
    for (std::size_t i = 0; i < edges.size();) {
      std::size_t end = i + 1;
      while (end < edges.size() && edges[end].first == edges[i].first) ++end;
      if (end - i == 2) {
        const std::uint64_t key = edges[i].first;
        for (std::uint32_t p : {std::uint32_t(key >> 32), std::uint32_t(key & 0xffffffffu)}) {
          const std::uint32_t a = root(cornerOf(edges[i].second, p)),
                              b = root(cornerOf(edges[i + 1].second, p));
          if (a != b) fanRoot[a] = b;
        }
      }
      i = end;
    }
  }
  Shape shape;
  std::vector<std::uint32_t> shapeOfCorner(nc);
  {
    std::vector<std::uint32_t> shapeOfRoot(nc, 0xffffffffu);
    for (std::size_t c = 0; c < nc; ++c) {
      std::uint32_t& s = shapeOfRoot[root(std::uint32_t(c))];
      if (s == 0xffffffffu) {
        s = std::uint32_t(shape.positions.size());
        shape.positions.push_back(uniquePos[corners[c]]);
        shape.locked.push_back(posLocked[corners[c]]);
      }
      shapeOfCorner[c] = s;
    }
  }
  shape.indices = shapeOfCorner;
  // wedges[firstWedge[s] .. firstWedge[s+1]) are the input vertices at shape vertex s.
  std::vector<std::uint32_t> firstWedge, wedges;
  {
    // The corners' input vertices bucketed by shape vertex, then each (small) bucket sorted and
    // without repeats.
    const std::size_t ns = shape.positions.size();
    std::vector<std::uint32_t> start(ns + 1, 0);
    for (std::size_t c = 0; c < nc; ++c) ++start[shapeOfCorner[c] + 1];
    for (std::size_t sv = 0; sv < ns; ++sv) start[sv + 1] += start[sv];
    std::vector<std::uint32_t> bucketed(nc);
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t c = 0; c < nc; ++c) bucketed[fill[shapeOfCorner[c]]++] = cornerVertex[c];
    firstWedge.assign(ns + 1, 0);
    wedges.reserve(nc);
    for (std::size_t sv = 0; sv < ns; ++sv) {
      const auto b = bucketed.begin() + start[sv], e = bucketed.begin() + start[sv + 1];
      std::sort(b, e);
      wedges.insert(wedges.end(), b, std::unique(b, e));
      firstWedge[sv + 1] = std::uint32_t(wedges.size());
    }
  }

  const ReducedShape reduced = guardedReduce(
      shape, targetTriangles, errorLimit,
      [this](const Shape& sh, std::size_t target, double limit) {
        return reduce(sh, target, limit);
      },
      clusterEveryRound);

  // Attributes back: per corner, the wedge whose normal best matches the kept triangle; among
  // equally good wedges (a flat texture seam) the one whose texture coordinate lies nearest the
  // triangle's other corners, so that a triangle does not span two atlas regions.
  const bool hasUv = mesh.texCoords.size() == nv;
  Mesh kept = mesh;
  kept.indices.clear();
  kept.indices.reserve(reduced.indices.size());
  std::vector<std::uint32_t> candidates[3];
  for (std::size_t i = 0; i + 2 < reduced.indices.size(); i += 3) {
    const std::uint32_t s[3] = {reduced.indices[i], reduced.indices[i + 1], reduced.indices[i + 2]};
    const glm::dvec3 n =
        triangleNormal(shape.positions[s[0]], shape.positions[s[1]], shape.positions[s[2]]);
    std::uint32_t chosen[3];
    bool ambiguous = false;
    for (int k = 0; k < 3; ++k) {
      candidates[k].clear();
      double best = -2.0;
      for (std::uint32_t w = firstWedge[s[k]]; w < firstWedge[s[k] + 1]; ++w)
        best = std::max(best, glm::dot(vertexNormal[wedges[w]], n));
      for (std::uint32_t w = firstWedge[s[k]]; w < firstWedge[s[k] + 1]; ++w)
        if (glm::dot(vertexNormal[wedges[w]], n) >= best - 1e-3) candidates[k].push_back(wedges[w]);
      chosen[k] = candidates[k].front();
      ambiguous = ambiguous || candidates[k].size() > 1;
    }
    if (ambiguous && hasUv) {
      // Two rounds: each corner moves to the candidate nearest the others' current choice.
      for (int round = 0; round < 2; ++round) {
        for (int k = 0; k < 3; ++k) {
          if (candidates[k].size() < 2) continue;
          const glm::vec2 ref =
              0.5f * (mesh.texCoords[chosen[(k + 1) % 3]] + mesh.texCoords[chosen[(k + 2) % 3]]);
          float bestDist = std::numeric_limits<float>::max();
          for (std::uint32_t w : candidates[k]) {
            const glm::vec2 d = mesh.texCoords[w] - ref;
            if (glm::dot(d, d) < bestDist) bestDist = glm::dot(d, d), chosen[k] = w;
          }
        }
      }
    }
    kept.indices.insert(kept.indices.end(), {chosen[0], chosen[1], chosen[2]});
  }
  SimplifiedMesh out;
  out.mesh = compactVertices(kept);
  out.geometricError = reduced.geometricError;
  return out;
}

Mesh weldVertices(const Mesh& mesh) {
  Mesh out = emptyLike(mesh);
  const std::size_t nv = mesh.positions.size();
  const bool hasN = mesh.normals.size() == nv;
  const bool hasUv = mesh.texCoords.size() == nv;
  std::unordered_map<WeldKey, std::uint32_t, WeldKeyHash> map;
  map.reserve(nv);
  std::vector<std::uint32_t> remap(nv);
  std::vector<glm::dvec3> normalSum;
  for (std::size_t v = 0; v < nv; ++v) {
    // -0.0 and 0.0 must weld: normalise the sign of zero before hashing bytes.
    WeldKey key{mesh.positions[v] + glm::dvec3(0.0),
                hasUv ? mesh.texCoords[v] + glm::vec2(0.0f) : glm::vec2(0.0f)};
    auto [it, fresh] = map.try_emplace(key, std::uint32_t(out.positions.size()));
    if (fresh) {
      out.positions.push_back(mesh.positions[v]);
      if (hasUv) out.texCoords.push_back(mesh.texCoords[v]);
      if (hasN) normalSum.emplace_back(0.0);
    }
    remap[v] = it->second;
    if (hasN) normalSum[it->second] += glm::dvec3(mesh.normals[v]);
  }
  if (hasN) {
    out.normals.resize(normalSum.size());
    for (std::size_t i = 0; i < normalSum.size(); ++i) {
      const double len = glm::length(normalSum[i]);
      out.normals[i] = len > 1e-12 && std::isfinite(len) ? glm::vec3(normalSum[i] / len)
                                                         : glm::vec3(0.0f, 0.0f, 1.0f);
    }
  }
  out.indices.reserve(mesh.indices.size());
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const auto a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
    if (a >= nv || b >= nv || c >= nv) continue;
    const auto ra = remap[a], rb = remap[b], rc = remap[c];
    if (ra == rb || rb == rc || ra == rc) continue;
    out.indices.insert(out.indices.end(), {ra, rb, rc});
  }
  return compactVertices(out);
}

Mesh compactVertices(const Mesh& mesh) {
  Mesh out = emptyLike(mesh);
  const std::size_t nv = mesh.positions.size();
  const bool hasN = mesh.normals.size() == nv;
  const bool hasUv = mesh.texCoords.size() == nv;
  std::vector<std::uint32_t> remap(nv, 0xffffffffu);
  out.indices.reserve(mesh.indices.size());
  for (std::uint32_t v : mesh.indices) {
    if (v >= nv) continue;
    if (remap[v] == 0xffffffffu) {
      remap[v] = std::uint32_t(out.positions.size());
      out.positions.push_back(mesh.positions[v]);
      if (hasN) out.normals.push_back(mesh.normals[v]);
      if (hasUv) out.texCoords.push_back(mesh.texCoords[v]);
    }
    out.indices.push_back(remap[v]);
  }
  return out;
}

}  // namespace hlod
