#pragma once
// Closest-point distance from a point to a set of triangles, and the first triangle a ray meets,
// through a bounding volume hierarchy (the surface metrics, the builder's texture baking, and the
// view-dependent builder's local Hausdorff distances use it).
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
  // No triangle tried first by within.
  static constexpr std::uint32_t kNoHint = 0xffffffffu;

  // triangles must not be empty.
  explicit TriangleBvh(std::vector<Triangle> triangles);

  // The distance from p to the closest point of any of the triangles, and its square (the
  // distance is the square root of distance2, exactly).
  double distance(const glm::dvec3& p) const;
  double distance2(const glm::dvec3& p) const;

  // Whether some triangle lies within r of p (stops at the first one found).
  bool within(const glm::dvec3& p, double r) const;
  // The same with r squared; hint (kNoHint, or what the last call left there) names a triangle
  // tried first, and is set to the one found. Queries at nearby points find their answer in the
  // triangle the last one found.
  bool within2(const glm::dvec3& p, double r2, std::uint32_t& hint) const;

  // The indices (into the constructor's vector) of the triangles no farther from p than the
  // closest one plus slack (>= 0), ascending: over an edge or a corner, every face that meets
  // there. closest2, when given, receives distance2(p); hint, as within2's, names a triangle
  // tried first and receives the closest one.
  std::vector<std::uint32_t> nearest(const glm::dvec3& p, double slack) const;

  // The first triangle the segment origin + t * direction, t in [0, tMax], meets (either face,
  // or with frontOnly only one whose front (counter-clockwise) faces the origin; a triangle
  // without area is never met): its index into the constructor's vector, t, and the
  // barycentric weights of its second and third corners at the point (the first's is
  // 1 - u - v). Möller and Trumbore, "Fast, minimum storage ray-triangle intersection" (1997).
  struct Hit {
    std::uint32_t triangle = kNoHint;
    double t = 0.0, u = 0.0, v = 0.0;
    explicit operator bool() const { return triangle != kNoHint; }
  };
  Hit firstHit(const glm::dvec3& origin, const glm::dvec3& direction, double tMax,
               bool frontOnly = false) const;
  void nearest(const glm::dvec3& p, double slack, std::vector<std::uint32_t>& out,
               double* closest2 = nullptr, std::uint32_t* hint = nullptr) const;

 private:
  // Float boxes, relative to origin_ and widened past rounding: half the bytes of doubles, and
  // still never nearer to a point than the triangles inside.
  struct Node {
    float min[3];
    std::uint32_t first;  // leaf: first triangle; inner: index of the right child
    float max[3];
    std::uint32_t count;  // leaf: triangle count; inner: 0 (the left child follows the node)
  };
  struct BuildItem {
    glm::vec3 centre;  // relative to origin_
    std::uint32_t id;
  };
  std::uint32_t build(std::vector<BuildItem>& items, std::uint32_t first, std::uint32_t count);
  static double boxDistance2(const glm::dvec3& q, const Node& node);
  double triangleDistance2(const glm::dvec3& p, std::uint32_t i) const;

  glm::dvec3 origin_{0.0};
  double margin_ = 0.0;
  std::vector<Triangle> triangles_;  // in leaf order
  std::vector<std::uint8_t> flat_;   // flat_[i]: triangles_[i] has no area (counts as its edges)
  std::vector<std::uint32_t> ids_;   // ids_[i]: the constructor's index of triangles_[i]
  std::vector<Node> nodes_;
};

}  // namespace hlod::metrics
