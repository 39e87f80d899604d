#include "hlod/Simplifier.h"

#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>

#include "build/SimplifierImpl.h"

namespace hlod {

Result<std::unique_ptr<Simplifier>> makeSimplifier(std::string_view name) {
  if (name == "meshopt") return std::unique_ptr<Simplifier>(makeMeshoptSimplifier());
  if (name == "openmesh") return std::unique_ptr<Simplifier>(makeOpenMeshSimplifier());
  return makeError("unknown simplifier '" + std::string(name) + "' (choose meshopt or openmesh)");
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
  return out;
}

}  // namespace

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
