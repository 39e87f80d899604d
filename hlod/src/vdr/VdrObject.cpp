// One object of view-dependent rendering: its hierarchies and wedges. See hlod/vdr/VdrObject.h.
#include "hlod/vdr/VdrObject.h"

#include <algorithm>
#include <cassert>
#include <numeric>

namespace hlod::vdr {

std::uint32_t VdrObject::cornerWedge(std::uint32_t t, int i, std::uint32_t at) const {
  const std::uint32_t own = faceWedges[t][std::size_t(i)];
  const std::uint32_t leaf = hierarchy.leafOf[at];
  if (wedgeLeaf[own] == leaf) return own;
  const std::uint32_t chart = wedgeChart[own];
  std::uint32_t best = leafWedgeStart[leaf];
  float bestDot = -2.0f;
  for (std::uint32_t w = leafWedgeStart[leaf]; w < leafWedgeStart[leaf + 1]; ++w) {
    if (wedgeChart[w] == chart) return w;
    const float d = glm::dot(wedgeNormal[w], wedgeNormal[own]);
    if (d > bestDot) bestDot = d, best = w;
  }
  return best;
}

Aabb VdrObject::bounds() const {
  Aabb b;
  for (const glm::dvec3& p : hierarchy.leafPosition) b.extend(p);
  return b;
}

std::uint64_t VdrObject::memoryBytes() const {
  const VertexHierarchy& h = hierarchy;
  std::uint64_t b = h.leafPosition.size() * sizeof(glm::dvec3) + h.faces.size() * 12 +
                    h.parent.size() * 4 + h.children.size() * 8 + h.leafOf.size() * 4 +
                    h.error.size() * 4 + h.radius.size() * 4 + h.neighbourhoodStart.size() * 4 +
                    h.storedFaces.size() * sizeof(StoredFace);
  b += clusters.clusters.size() * sizeof(Cluster) + clusters.clusterOf.size() * 4;
  b += wedgeLeaf.size() * 4 + wedgeNormal.size() * 12 + wedgeTexCoord.size() * 8 +
       wedgeChart.size() * 4 + leafWedgeStart.size() * 4 + faceWedges.size() * 12;
  if (texture) b += texture->pixels.size();
  return b;
}

Result<VdrObject> buildVdrObject(const Mesh& input, const std::vector<std::uint8_t>& inputLocked,
                                 const VdrBuildOptions& options) {
  // Unused vertices would be leaves without faces: renumber the used ones in order of first
  // use, carrying their lock flags.
  Mesh mesh;
  std::vector<std::uint8_t> locked;
  {
    std::vector<std::uint32_t> newIndex(input.positions.size(), kNone);
    Mesh out;
    out.name = input.name;
    out.baseColor = input.baseColor;
    out.texture = input.texture;
    out.oneSided = input.oneSided;
    const bool hasN = input.normals.size() == input.positions.size();
    const bool hasUv = input.texCoords.size() == input.positions.size();
    for (std::uint32_t i : input.indices) {
      if (i >= input.positions.size()) return makeError("a face index is out of range");
      if (newIndex[i] == kNone) {
        newIndex[i] = std::uint32_t(out.positions.size());
        out.positions.push_back(input.positions[i]);
        if (hasN) out.normals.push_back(input.normals[i]);
        if (hasUv) out.texCoords.push_back(input.texCoords[i]);
        if (!inputLocked.empty()) locked.push_back(i < inputLocked.size() ? inputLocked[i] : 0);
      }
      out.indices.push_back(newIndex[i]);
    }
    mesh = std::move(out);
  }
  if (mesh.normals.size() != mesh.positions.size())
    mesh.normals = computeVertexNormals(mesh.positions, mesh.indices);

  std::vector<std::uint32_t> positionOf;
  std::vector<std::array<std::uint32_t, 3>> faceVertices;
  HierarchyInput in = hierarchyInputOf(mesh, locked, &positionOf, &faceVertices);
  if (in.faces.empty()) return makeError("the mesh has no faces to build a vertex hierarchy of");
  HierarchyOptions ho = options.hierarchy;
  if (!(ho.virtualEdgeDistance > 0.0) && options.virtualEdgeFraction > 0.0)
    ho.virtualEdgeDistance = options.virtualEdgeFraction * glm::length(mesh.bounds().size());
  auto hierarchy = buildVertexHierarchy(in, ho);
  if (!hierarchy) return hierarchy.error();

  VdrObject o;
  o.centre = mesh.bounds().centre();
  o.baseColor = mesh.baseColor;
  o.oneSided = mesh.oneSided;
  const bool hasUv = mesh.texCoords.size() == mesh.positions.size();
  if (hasUv && mesh.texture && !mesh.texture->empty()) o.texture = mesh.texture;
  // Wedges: the mesh's vertices, sorted by their leaf (stable: the mesh's order within one).
  const auto n = std::uint32_t(mesh.positions.size());
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return positionOf[a] < positionOf[b]; });
  std::vector<std::uint32_t> wedgeOf(n);
  for (std::uint32_t w = 0; w < n; ++w) wedgeOf[order[w]] = w;
  // Charts: wedges joined through the faces that share them.
  std::vector<std::uint32_t> chart(n);
  std::iota(chart.begin(), chart.end(), 0u);
  const auto find = [&](std::uint32_t x) {
    while (chart[x] != x) x = chart[x] = chart[chart[x]];
    return x;
  };
  for (const auto& f : faceVertices) {
    const std::uint32_t r = find(f[0]);
    chart[find(f[1])] = r;
    chart[find(f[2])] = r;
  }
  const std::uint32_t leaves = hierarchy->leafCount;
  o.leafWedgeStart.assign(leaves + 1, 0);
  for (std::uint32_t w = 0; w < n; ++w) {
    const std::uint32_t v = order[w];
    o.wedgeLeaf.push_back(positionOf[v]);
    o.wedgeNormal.push_back(mesh.normals[v]);
    if (hasUv) o.wedgeTexCoord.push_back(mesh.texCoords[v]);
    o.wedgeChart.push_back(wedgeOf[find(v)]);
    ++o.leafWedgeStart[positionOf[v] + 1];
  }
  for (std::uint32_t l = 0; l < leaves; ++l) o.leafWedgeStart[l + 1] += o.leafWedgeStart[l];
  for (const auto& f : faceVertices)
    o.faceWedges.push_back({wedgeOf[f[0]], wedgeOf[f[1]], wedgeOf[f[2]]});
  assert(o.faceWedges.size() == hierarchy->faces.size());
  ClusterOptions co = options.clusters;
  if (!(co.errorFloor > 0.0) && options.errorFloorFraction > 0.0)
    co.errorFloor = options.errorFloorFraction * glm::length(mesh.bounds().size());
  o.clusters = buildClusterHierarchy(*hierarchy, co);
  o.hierarchy = std::move(*hierarchy);
  return o;
}

}  // namespace hlod::vdr
