#include "hlod/Mesh.h"

#include <algorithm>
#include <cmath>

namespace hlod {

Aabb Mesh::bounds() const {
  Aabb box;
  for (const auto& p : positions) box.extend(p);
  return box;
}

std::size_t Model::triangleCount() const {
  std::size_t n = 0;
  for (const auto& m : meshes) n += m.triangleCount();
  return n;
}

Aabb Model::bounds() const {
  Aabb box;
  for (const auto& m : meshes) box.extend(m.bounds());
  return box;
}

std::size_t Model::objectCount() const {
  std::size_t n = 0;
  for (const ObjectRun& r : objectRuns) n = std::max<std::size_t>(n, std::size_t(r.object) + 1);
  return objectRuns.empty() ? 1 : n;
}

std::vector<glm::vec3> computeVertexNormals(const std::vector<glm::dvec3>& positions,
                                            const std::vector<std::uint32_t>& indices) {
  std::vector<glm::dvec3> acc(positions.size(), glm::dvec3(0.0));
  for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
    const auto a = indices[i], b = indices[i + 1], c = indices[i + 2];
    if (a >= positions.size() || b >= positions.size() || c >= positions.size()) continue;
    // The unnormalised cross product weights each face by twice its area.
    const glm::dvec3 n = glm::cross(positions[b] - positions[a], positions[c] - positions[a]);
    acc[a] += n;
    acc[b] += n;
    acc[c] += n;
  }
  std::vector<glm::vec3> out(positions.size());
  for (std::size_t i = 0; i < acc.size(); ++i) {
    const double len = glm::length(acc[i]);
    out[i] = (len > 0.0 && std::isfinite(len)) ? glm::vec3(acc[i] / len) : glm::vec3(0, 0, 1);
  }
  return out;
}

LocalMesh toLocal(const Mesh& mesh) {
  LocalMesh out;
  out.centre = mesh.bounds().centre();
  if (mesh.positions.empty()) out.centre = glm::dvec3(0.0);
  out.positions.reserve(mesh.positions.size());
  for (const auto& p : mesh.positions) out.positions.emplace_back(p - out.centre);
  out.normals = mesh.normals.size() == mesh.positions.size()
                    ? mesh.normals
                    : computeVertexNormals(mesh.positions, mesh.indices);
  if (mesh.texCoords.size() == mesh.positions.size()) out.texCoords = mesh.texCoords;
  out.indices = mesh.indices;
  out.baseColor = mesh.baseColor;
  out.texture = mesh.texture;
  out.oneSided = mesh.oneSided;
  out.progression = mesh.progression;
  return out;
}

}  // namespace hlod
