#include "metrics/TriangleBvh.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace hlod::metrics {

namespace {

constexpr std::uint32_t kLeafSize = 4;

double segmentDistance2(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  const glm::dvec3 d = p - (a + t * ab);
  return glm::dot(d, d);
}

double boxDistance2(const glm::dvec3& p, const Aabb& box) {
  const glm::dvec3 d = glm::max(glm::max(box.min - p, p - box.max), glm::dvec3(0.0));
  return glm::dot(d, d);
}

double edgesDistance2(const glm::dvec3& p, const Triangle& t) {
  return std::min({segmentDistance2(p, t[0], t[1]), segmentDistance2(p, t[1], t[2]),
                   segmentDistance2(p, t[2], t[0])});
}

// Squared distance to the closest point: Ericson, "Real-Time Collision Detection" (2005), sec.
// 5.1.5, which finds the Voronoi region of p (a corner, an edge or the face) from dot products.
double faceDistance2(const glm::dvec3& p, const Triangle& t) {
  const glm::dvec3& a = t[0];
  const glm::dvec3& b = t[1];
  const glm::dvec3& c = t[2];
  const glm::dvec3 ab = b - a;
  const glm::dvec3 ac = c - a;
  const auto distance2 = [&](const glm::dvec3& q) { return glm::dot(p - q, p - q); };
  const glm::dvec3 ap = p - a;
  const double d1 = glm::dot(ab, ap);
  const double d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return distance2(a);
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp);
  const double d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return distance2(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return distance2(a + d1 / (d1 - d3) * ab);
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp);
  const double d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return distance2(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return distance2(a + d2 / (d2 - d6) * ac);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    return distance2(b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b));
  }
  const double denominator = va + vb + vc;
  return distance2(a + (vb / denominator) * ab + (vc / denominator) * ac);
}

double pointTriangleDistance2(const glm::dvec3& p, const Triangle& t) {
  // Collinear or coincident corners: the region tests would divide by ~0; such a triangle is
  // its edges. So is one whose squares underflow (a NaN from the face test).
  const glm::dvec3 ab = t[1] - t[0];
  const glm::dvec3 ac = t[2] - t[0];
  const glm::dvec3 n = glm::cross(ab, ac);
  if (glm::dot(n, n) <= 1e-24 * glm::dot(ab, ab) * glm::dot(ac, ac)) return edgesDistance2(p, t);
  const double d2 = faceDistance2(p, t);
  return std::isfinite(d2) ? d2 : edgesDistance2(p, t);
}

}  // namespace

double pointTriangleDistance(const glm::dvec3& p, const Triangle& t) {
  return std::sqrt(pointTriangleDistance2(p, t));
}

TriangleBvh::TriangleBvh(std::vector<Triangle> triangles) {
  assert(!triangles.empty());
  // Built on (triangle, id) items, contiguous for the splits; split into the two arrays after.
  std::vector<Item> items(triangles.size());
  for (std::uint32_t i = 0; i < items.size(); ++i) items[i] = {triangles[i], i};
  triangles = {};
  nodes_.reserve(2 * items.size() / kLeafSize + 1);
  build(items, 0, static_cast<std::uint32_t>(items.size()));
  triangles_.resize(items.size());
  ids_.resize(items.size());
  for (std::size_t i = 0; i < items.size(); ++i) triangles_[i] = items[i].t, ids_[i] = items[i].id;
}

// Median split along the longest axis of the centroids' box; the left child is stored right
// after its parent.
std::uint32_t TriangleBvh::build(std::vector<Item>& items, std::uint32_t first,
                                 std::uint32_t count) {
  const std::uint32_t index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back({});
  Aabb box, centres;
  for (std::uint32_t i = first; i < first + count; ++i) {
    const Triangle& t = items[i].t;
    for (const glm::dvec3& v : t) box.extend(v);
    centres.extend((t[0] + t[1] + t[2]) / 3.0);
  }
  nodes_[index].box = box;
  if (count <= kLeafSize) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  const glm::dvec3 extent = centres.size();
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const std::uint32_t half = count / 2;
  const auto centre = [axis](const Item& it) {
    return it.t[0][axis] + it.t[1][axis] + it.t[2][axis];
  };
  std::nth_element(items.begin() + first, items.begin() + first + half,
                   items.begin() + first + count,
                   [&](const Item& l, const Item& r) { return centre(l) < centre(r); });
  build(items, first, half);
  const std::uint32_t right = build(items, first + half, count - half);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

double TriangleBvh::distance(const glm::dvec3& p) const {
  double best2 = std::numeric_limits<double>::infinity();
  // Depth-first, the nearer child first, skipping boxes no nearer than the best so far.
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (boxDistance2(p, node.box) >= best2) continue;
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
        best2 = std::min(best2, pointTriangleDistance2(p, triangles_[i]));
      }
      continue;
    }
    const std::uint32_t left = static_cast<std::uint32_t>(&node - nodes_.data()) + 1;
    const std::uint32_t right = node.first;
    const double dl = boxDistance2(p, nodes_[left].box);
    const double dr = boxDistance2(p, nodes_[right].box);
    const bool leftFirst = dl <= dr;
    assert(top + 2 <= 64);  // depth-first: at most one more entry per level (depth < 40)
    const std::uint32_t nearer = leftFirst ? left : right;
    const std::uint32_t farther = leftFirst ? right : left;
    if ((leftFirst ? dr : dl) < best2) stack[top++] = farther;
    if ((leftFirst ? dl : dr) < best2) stack[top++] = nearer;
  }
  return std::sqrt(best2);
}

bool TriangleBvh::within(const glm::dvec3& p, double r) const {
  const double r2 = r * r;
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (boxDistance2(p, node.box) > r2) continue;
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
        if (pointTriangleDistance2(p, triangles_[i]) <= r2) return true;
      continue;
    }
    assert(top + 2 <= 64);
    stack[top++] = node.first;
    stack[top++] = static_cast<std::uint32_t>(&node - nodes_.data()) + 1;
  }
  return false;
}

std::vector<std::uint32_t> TriangleBvh::nearest(const glm::dvec3& p, double slack) const {
  assert(slack >= 0.0);
  const double limit = distance(p) + slack;
  const double limit2 = limit * limit;
  std::vector<std::uint32_t> out;
  std::vector<std::uint32_t> stack{0};
  while (!stack.empty()) {
    const Node& node = nodes_[stack.back()];
    stack.pop_back();
    if (boxDistance2(p, node.box) > limit2) continue;
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
        if (pointTriangleDistance2(p, triangles_[i]) <= limit2) out.push_back(ids_[i]);
      continue;
    }
    stack.push_back(static_cast<std::uint32_t>(&node - nodes_.data()) + 1);
    stack.push_back(node.first);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace hlod::metrics
