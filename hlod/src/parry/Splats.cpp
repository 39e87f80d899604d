#include "hlod/parry/Splats.h"

#include <algorithm>
#include <limits>

#include "hlod/parry/SphereHierarchy.h"

namespace hlod {

std::vector<Splat> makeSplats(const LocalMesh& mesh, std::size_t count) {
  const std::size_t nv = mesh.positions.size();
  // The vertices the triangles use (a Parry node also holds the parents its progression makes),
  // each a leaf sphere of half its longest edge.
  std::vector<double> longest(nv, -1.0);
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = mesh.indices[i + k], b = mesh.indices[i + (k + 1) % 3];
      const double l = glm::length(glm::dvec3(mesh.positions[a] - mesh.positions[b]));
      longest[a] = std::max(longest[a], l);
      longest[b] = std::max(longest[b], l);
    }
  std::vector<SphereVertex> vertices;
  std::vector<std::uint32_t> vertexOf;
  const bool hasUv = mesh.texCoords.size() == nv;
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (longest[v] < 0.0) continue;
    SphereVertex s;
    s.position = glm::dvec3(mesh.positions[v]);
    s.normal = mesh.normals.size() == nv ? mesh.normals[v] : glm::vec3(0, 0, 1);
    s.radius = 0.5 * longest[v];
    vertices.push_back(s);
    vertexOf.push_back(v);
  }
  if (vertices.empty()) return {};
  const SphereHierarchy h = buildSphereHierarchy(vertices);
  std::vector<Splat> out;
  for (std::uint32_t n : sphereCut(h, count)) {
    const SphereNode& node = h.nodes[n];
    Splat s;
    s.position = glm::vec3(node.centre);
    s.radius = float(node.radius);
    s.normal = node.normal;
    if (hasUv) {
      // The texture coordinate of the leaf nearest the centre.
      double best = std::numeric_limits<double>::max();
      std::vector<std::uint32_t> stack{n};
      while (!stack.empty()) {
        const std::uint32_t x = stack.back();
        stack.pop_back();
        if (!h.nodes[x].isLeaf()) {
          stack.insert(stack.end(), {h.nodes[x].child[0], h.nodes[x].child[1]});
          continue;
        }
        const double d = glm::length(h.nodes[x].centre - node.centre);
        if (d < best) best = d, s.texCoord = mesh.texCoords[vertexOf[x]];
      }
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace hlod
