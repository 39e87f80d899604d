#pragma once
// Closest-point distance from a point to a set of triangles, through a bounding volume hierarchy
// (private to metrics/).
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"

namespace hlod::metrics {

using Triangle = std::array<glm::dvec3, 3>;

// The distance from p to the closest point of triangle t. Degenerate triangles (collinear or
// coincident corners) count as their edges; never NaN for finite input.
double pointTriangleDistance(const glm::dvec3& p, const Triangle& t);

class TriangleBvh {
 public:
  // triangles must not be empty.
  explicit TriangleBvh(std::vector<Triangle> triangles);

  // The distance from p to the closest point of any of the triangles.
  double distance(const glm::dvec3& p) const;

  // Whether some triangle lies within r of p (stops at the first one found).
  bool within(const glm::dvec3& p, double r) const;

  // The indices (into the constructor's vector) of the triangles no farther from p than the
  // closest one plus slack (>= 0): over an edge or a corner, every face that meets there.
  std::vector<std::uint32_t> nearest(const glm::dvec3& p, double slack) const;

 private:
  struct Node {
    Aabb box;
    std::uint32_t first = 0;  // leaf: first triangle; inner: index of the right child
    std::uint32_t count = 0;  // leaf: triangle count; inner: 0 (the left child follows the node)
  };
  struct Item {
    Triangle t;
    std::uint32_t id;
  };
  std::uint32_t build(std::vector<Item>& items, std::uint32_t first, std::uint32_t count);

  std::vector<Triangle> triangles_;  // in leaf order
  std::vector<std::uint32_t> ids_;   // ids_[i]: the constructor's index of triangles_[i]
  std::vector<Node> nodes_;
};

}  // namespace hlod::metrics
