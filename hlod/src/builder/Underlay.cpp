// A cell node's underlay (builder/Underlay.h).
#include "builder/Underlay.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace hlod {

void addUnderlay(Mesh& mesh, const Mesh& input, std::vector<glm::vec4>& colours, const Aabb& box,
                 UpAxis up) {
  const int u = int(up), e0 = (u + 1) % 3, e1 = (u + 2) % 3;  // e0 x e1 = +up
  const double size = std::max(box.max[e0] - box.min[e0], box.max[e1] - box.min[e1]);
  // The colour of the lowest ground: the input's triangles facing up within a metre of the
  // bottom, weighted by area.
  glm::dvec4 sum(0.0);
  double weight = 0.0;
  for (std::size_t i = 0; i + 2 < input.indices.size(); i += 3) {
    const glm::dvec3 a = input.positions[input.indices[i]],
                     b = input.positions[input.indices[i + 1]],
                     c = input.positions[input.indices[i + 2]];
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double area = 0.5 * glm::length(n);
    if (!(area > 0.0) || n[u] < 0.9 * 2.0 * area || std::min({a[u], b[u], c[u]}) > box.min[u] + 1.0)
      continue;
    for (int k = 0; k < 3; ++k)
      sum += area * glm::dvec4(colours[std::size_t(input.texCoords[input.indices[i + k]].x)]);
    weight += 3.0 * area;
  }
  if (!(weight > 0.0)) return;
  const auto colour = float(colours.size());
  colours.push_back(glm::vec4(sum / weight));
  const double depth = box.min[u] - kUnderlayDepth * size;
  const auto base = std::uint32_t(mesh.positions.size());
  for (const auto& [x, y] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
    glm::dvec3 p(0.0);
    p[u] = depth;
    p[e0] = x ? box.max[e0] : box.min[e0];
    p[e1] = y ? box.max[e1] : box.min[e1];
    mesh.positions.push_back(p);
    glm::vec3 n(0.0f);
    n[u] = 1.0f;
    mesh.normals.push_back(n);
    mesh.texCoords.emplace_back(colour, 0.0f);
  }
  mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

}  // namespace hlod
