// Lakhia et al., "Interactive rendering of large city models", sec. III-B, eqs. 1-3.
#include "builder/Preprocess.h"

#include <cmath>

namespace hlod {

double nodeCost(std::uint64_t numTexTri, std::uint64_t numUnTexTri, double cTex) {
  return double(numTexTri) * cTex + double(numUnTexTri) * (1.0 - cTex);
}

double staticBenefit(std::uint64_t numTri, double area) {
  return std::sqrt(double(numTri) * std::max(area, 0.0));
}

glm::vec3 averageNormal(const Mesh& mesh) {
  // normal_t * area_t is half the cross product: the halves cancel in the normalisation.
  glm::dvec3 sum(0.0);
  const std::size_t nv = mesh.positions.size();
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const auto a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
    if (a >= nv || b >= nv || c >= nv) continue;
    sum += glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
  }
  const double len = glm::length(sum);
  if (!(len > 0.0) || !std::isfinite(len)) return {0.0f, 0.0f, 1.0f};
  const glm::vec3 n(sum / len);
  if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) return {0.0f, 0.0f, 1.0f};
  return n;
}

NodeMeasures measureNode(const Mesh& mesh, double cTex) {
  NodeMeasures m;
  m.bounds = mesh.bounds();
  m.numTri = static_cast<std::uint32_t>(mesh.triangleCount());
  const bool textured =
      mesh.texture && !mesh.texture->empty() && mesh.texCoords.size() == mesh.positions.size();
  m.numTexTri = textured ? m.numTri : 0;
  m.area = surfaceArea(mesh);
  m.cost = nodeCost(m.numTexTri, m.numTri - m.numTexTri, cTex);
  m.staticBenefit = staticBenefit(m.numTri, m.area);
  m.avgNormal = averageNormal(mesh);
  return m;
}

double surfaceArea(const Mesh& mesh) {
  double area = 0.0;
  const std::size_t nv = mesh.positions.size();
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const auto a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
    if (a >= nv || b >= nv || c >= nv) continue;
    area += 0.5 * glm::length(glm::cross(mesh.positions[b] - mesh.positions[a],
                                         mesh.positions[c] - mesh.positions[a]));
  }
  return area;
}

void describeNode(NodeInfo& info, const Mesh& mesh, double cTex) {
  const NodeMeasures m = measureNode(mesh, cTex);
  info.numTri = m.numTri;
  info.numTexTri = m.numTexTri;
  const auto decimated = std::uint32_t(mesh.progression.decimated());
  info.minTri = decimated > 0 ? info.numTri - decimated : 0;
  info.cost = m.cost;
  info.staticBenefit = m.staticBenefit;
  info.avgNormal = m.avgNormal;
}

LocalMesh localAround(const Mesh& mesh, const glm::dvec3& centre) {
  LocalMesh local = toLocal(mesh);
  local.centre = centre;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    local.positions[v] = glm::vec3(mesh.positions[v] - centre);
  return local;
}

}  // namespace hlod
