#include "hlod/metrics/TriangleBvh.h"

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

// Collinear or coincident corners: the region tests would divide by ~0; such a triangle is its
// edges.
bool isFlat(const Triangle& t) {
  const glm::dvec3 ab = t[1] - t[0];
  const glm::dvec3 ac = t[2] - t[0];
  const glm::dvec3 n = glm::cross(ab, ac);
  return glm::dot(n, n) <= 1e-24 * glm::dot(ab, ab) * glm::dot(ac, ac);
}

double pointTriangleDistance2(const glm::dvec3& p, const Triangle& t, bool flat) {
  if (flat) return edgesDistance2(p, t);
  // So is one whose squares underflow (a NaN from the face test).
  const double d2 = faceDistance2(p, t);
  return std::isfinite(d2) ? d2 : edgesDistance2(p, t);
}

// The float just below (down) or above x: a box rounded outwards.
float floatDown(double x) {
  const float f = static_cast<float>(x);
  return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float floatUp(double x) {
  const float f = static_cast<float>(x);
  return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

}  // namespace

double pointTriangleDistance(const glm::dvec3& p, const Triangle& t) {
  return std::sqrt(pointTriangleDistance2(p, t, isFlat(t)));
}

TriangleBvh::TriangleBvh(std::vector<Triangle> triangles) {
  assert(!triangles.empty());
  const auto n = static_cast<std::uint32_t>(triangles.size());
  Aabb all;
  for (const Triangle& t : triangles)
    for (const glm::dvec3& v : t) all.extend(v);
  origin_ = all.centre();
  // Far above the rounding of the relative coordinates and of the distances (about 1e-16 of the
  // coordinates' magnitude), far below any distance that matters.
  const glm::dvec3 magnitude = glm::abs(origin_) + all.size();
  margin_ = 1e-9 * std::max({magnitude.x, magnitude.y, magnitude.z});
  // The splits move small items (a centroid in float: any split is right, only the tree's shape
  // depends on it), not the triangles, which are put in leaf order once, at the end.
  std::vector<BuildItem> items(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const Triangle& t = triangles[i];
    items[i] = {glm::vec3((t[0] + t[1] + t[2]) / 3.0 - origin_), i};
  }
  nodes_.reserve(2 * n / kLeafSize + 1);
  build(items, 0, n);
  ids_.reserve(n);
  for (const BuildItem& item : items) ids_.push_back(item.id);
  items = {};
  // The triangles into leaf order in place (triangles_[i] = triangles[ids_[i]]), cycle by cycle:
  // no second copy of them. flat_ marks the places done until it gets its meaning.
  flat_.assign(n, 0);
  for (std::uint32_t start = 0; start < n; ++start) {
    if (flat_[start]) continue;
    const Triangle saved = triangles[start];
    std::uint32_t i = start;
    for (;;) {
      flat_[i] = 1;
      const std::uint32_t from = ids_[i];
      if (from == start) {
        triangles[i] = saved;
        break;
      }
      triangles[i] = triangles[from];
      i = from;
    }
  }
  triangles_ = std::move(triangles);
  for (std::uint32_t i = 0; i < n; ++i) flat_[i] = isFlat(triangles_[i]);
  // Boxes bottom up (children follow their parent): a leaf's from its triangles, a parent's the
  // union of its children's.
  for (std::size_t k = nodes_.size(); k-- > 0;) {
    Node& node = nodes_[k];
    if (node.count == 0) {
      const Node& l = nodes_[k + 1];
      const Node& r = nodes_[node.first];
      for (int a = 0; a < 3; ++a) {
        node.min[a] = std::min(l.min[a], r.min[a]);
        node.max[a] = std::max(l.max[a], r.max[a]);
      }
      continue;
    }
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
      for (const glm::dvec3& v : triangles_[i]) {
        lo = glm::min(lo, v - origin_);
        hi = glm::max(hi, v - origin_);
      }
    for (int a = 0; a < 3; ++a) {
      node.min[a] = floatDown(lo[a] - margin_);
      node.max[a] = floatUp(hi[a] + margin_);
    }
  }
}

// Median split along the longest axis of the centroids' box; the left child is stored right
// after its parent.
std::uint32_t TriangleBvh::build(std::vector<BuildItem>& items, std::uint32_t first,
                                 std::uint32_t count) {
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back({});
  if (count <= kLeafSize) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  glm::vec3 lo = items[first].centre, hi = lo;
  for (std::uint32_t i = first + 1; i < first + count; ++i) {
    lo = glm::min(lo, items[i].centre);
    hi = glm::max(hi, items[i].centre);
  }
  const glm::vec3 extent = hi - lo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const std::uint32_t half = count / 2;
  std::nth_element(
      items.begin() + first, items.begin() + first + half, items.begin() + first + count,
      [axis](const BuildItem& l, const BuildItem& r) { return l.centre[axis] < r.centre[axis]; });
  build(items, first, half);
  const std::uint32_t right = build(items, first + half, count - half);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

// Squared distance from q to the node's box (both relative to origin_).
inline double TriangleBvh::boxDistance2(const glm::dvec3& q, const Node& node) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double below = double(node.min[k]) - q[k];
    const double above = q[k] - double(node.max[k]);
    const double d = below > 0.0 ? below : above > 0.0 ? above : 0.0;
    d2 += d * d;
  }
  return d2;
}

inline double TriangleBvh::triangleDistance2(const glm::dvec3& p, std::uint32_t i) const {
  return pointTriangleDistance2(p, triangles_[i], flat_[i] != 0);
}

double TriangleBvh::distance(const glm::dvec3& p) const {
  return std::sqrt(distance2(p));
}

double TriangleBvh::distance2(const glm::dvec3& p) const {
  const glm::dvec3 q = p - origin_;
  double best2 = std::numeric_limits<double>::infinity();
  // Depth-first, the nearer child first, skipping boxes no nearer than the best so far (each
  // box's distance kept with it on the stack).
  struct Entry {
    std::uint32_t node;
    double d2;
  };
  Entry stack[64];
  int top = 0;
  stack[top++] = {0, boxDistance2(q, nodes_[0])};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d2 >= best2) continue;
    const Node& node = nodes_[e.node];
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
        best2 = std::min(best2, triangleDistance2(p, i));
      continue;
    }
    const Entry left{e.node + 1, boxDistance2(q, nodes_[e.node + 1])};
    const Entry right{node.first, boxDistance2(q, nodes_[node.first])};
    const bool leftFirst = left.d2 <= right.d2;
    assert(top + 2 <= 64);  // depth-first: at most one more entry per level (depth < 40)
    const Entry& nearer = leftFirst ? left : right;
    const Entry& farther = leftFirst ? right : left;
    if (farther.d2 < best2) stack[top++] = farther;
    if (nearer.d2 < best2) stack[top++] = nearer;
  }
  return best2;
}

bool TriangleBvh::within(const glm::dvec3& p, double r) const {
  std::uint32_t hint = kNoHint;
  return within2(p, r * r, hint);
}

bool TriangleBvh::within2(const glm::dvec3& p, double r2, std::uint32_t& hint) const {
  if (hint < triangles_.size() && triangleDistance2(p, hint) <= r2) return true;
  const glm::dvec3 q = p - origin_;
  if (boxDistance2(q, nodes_[0]) > r2) return false;
  // The nearer child first: the search ends at the first triangle found.
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::uint32_t index = stack[--top];
    const Node& node = nodes_[index];
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
        if (triangleDistance2(p, i) <= r2) {
          hint = i;
          return true;
        }
      continue;
    }
    const double dl = boxDistance2(q, nodes_[index + 1]);
    const double dr = boxDistance2(q, nodes_[node.first]);
    const bool leftFirst = dl <= dr;
    assert(top + 2 <= 64);
    if ((leftFirst ? dr : dl) <= r2) stack[top++] = leftFirst ? node.first : index + 1;
    if ((leftFirst ? dl : dr) <= r2) stack[top++] = leftFirst ? index + 1 : node.first;
  }
  return false;
}

std::vector<std::uint32_t> TriangleBvh::nearest(const glm::dvec3& p, double slack) const {
  std::vector<std::uint32_t> out;
  nearest(p, slack, out);
  return out;
}

void TriangleBvh::nearest(const glm::dvec3& p, double slack, std::vector<std::uint32_t>& out,
                          double* closest2, std::uint32_t* hint) const {
  assert(slack >= 0.0);
  // One pass: the closest distance so far plus slack bounds the search (it only shrinks), so
  // every triangle within the final bound is met; those past it go at the end. The hint's
  // triangle, taken first, bounds it from the start.
  const glm::dvec3 q = p - origin_;
  double best2 = std::numeric_limits<double>::infinity();
  double bound2 = best2;
  std::uint32_t closest = kNoHint;
  const std::uint32_t first = hint && *hint < triangles_.size() ? *hint : kNoHint;
  out.clear();  // leaf indices first
  if (first != kNoHint) {
    best2 = triangleDistance2(p, first);
    const double bound = std::sqrt(best2) + slack;
    bound2 = bound * bound;
    closest = first;
    out.push_back(first);
  }
  struct Entry {
    std::uint32_t node;
    double d2;
  };
  Entry stack[64];
  int top = 0;
  stack[top++] = {0, boxDistance2(q, nodes_[0])};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d2 > bound2) continue;
    const Node& node = nodes_[e.node];
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
        if (i == first) continue;
        const double d2 = triangleDistance2(p, i);
        if (d2 < best2) {
          best2 = d2;
          closest = i;
          const double bound = std::sqrt(best2) + slack;
          bound2 = bound * bound;
        }
        if (d2 <= bound2) out.push_back(i);
      }
      continue;
    }
    const Entry left{e.node + 1, boxDistance2(q, nodes_[e.node + 1])};
    const Entry right{node.first, boxDistance2(q, nodes_[node.first])};
    const bool leftFirst = left.d2 <= right.d2;
    assert(top + 2 <= 64);
    const Entry& nearer = leftFirst ? left : right;
    const Entry& farther = leftFirst ? right : left;
    if (farther.d2 <= bound2) stack[top++] = farther;
    if (nearer.d2 <= bound2) stack[top++] = nearer;
  }
  if (closest2) *closest2 = best2;
  if (hint) *hint = closest;
  std::size_t kept = 0;
  for (std::uint32_t i : out)
    if (triangleDistance2(p, i) <= bound2) out[kept++] = ids_[i];
  out.resize(kept);
  std::sort(out.begin(), out.end());
}

TriangleBvh::Hit TriangleBvh::firstHit(const glm::dvec3& origin, const glm::dvec3& direction,
                                       double tMax, bool frontOnly) const {
  Hit hit;
  const glm::dvec3 o = origin - origin_;
  const glm::dvec3 inv(1.0 / direction.x, 1.0 / direction.y, 1.0 / direction.z);
  double best = tMax;
  // The segment's entry into a box (slabs), or infinity when it misses it before `best`.
  const auto enter = [&](const Node& node) {
    double t0 = 0.0, t1 = best;
    for (int k = 0; k < 3; ++k) {
      double a = (double(node.min[k]) - o[k]) * inv[k], b = (double(node.max[k]) - o[k]) * inv[k];
      if (a > b) std::swap(a, b);
      // A direction of 0 along k: inside the slab (a -inf, b +inf) or outside (NaN-free +-inf).
      if (std::isnan(a) || std::isnan(b)) {
        if (o[k] < double(node.min[k]) || o[k] > double(node.max[k]))
          return std::numeric_limits<double>::infinity();
        continue;
      }
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
    }
    return t0 <= t1 ? t0 : std::numeric_limits<double>::infinity();
  };
  struct Entry {
    std::uint32_t node;
    double t;
  };
  Entry stack[64];
  int top = 0;
  if (const double t = enter(nodes_[0]); std::isfinite(t)) stack[top++] = {0, t};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.t > best) continue;
    const Node& node = nodes_[e.node];
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
        if (flat_[i]) continue;
        const Triangle& tri = triangles_[i];
        const glm::dvec3 e1 = tri[1] - tri[0], e2 = tri[2] - tri[0];
        const glm::dvec3 pv = glm::cross(direction, e2);
        // det = -direction . (e1 x e2): positive where the front faces the origin.
        const double det = glm::dot(e1, pv);
        if (det == 0.0 || !std::isfinite(det) || (frontOnly && det < 0.0)) continue;
        const double invDet = 1.0 / det;
        const glm::dvec3 tv = origin - tri[0];
        const double u = glm::dot(tv, pv) * invDet;
        if (u < 0.0 || u > 1.0) continue;
        const glm::dvec3 qv = glm::cross(tv, e1);
        const double v = glm::dot(direction, qv) * invDet;
        if (v < 0.0 || u + v > 1.0) continue;
        const double t = glm::dot(e2, qv) * invDet;
        if (t < 0.0 || t > best) continue;
        best = t;
        hit = {ids_[i], t, u, v};
      }
      continue;
    }
    const Entry left{e.node + 1, enter(nodes_[e.node + 1])};
    const Entry right{node.first, enter(nodes_[node.first])};
    const bool leftFirst = left.t <= right.t;
    assert(top + 2 <= 64);
    const Entry& nearer = leftFirst ? left : right;
    const Entry& farther = leftFirst ? right : left;
    if (std::isfinite(farther.t)) stack[top++] = farther;
    if (std::isfinite(nearer.t)) stack[top++] = nearer;
  }
  return hit;
}

}  // namespace hlod::metrics
