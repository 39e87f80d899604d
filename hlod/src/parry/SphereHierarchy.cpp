// Parry et al. sec. 5: the bounding-sphere hierarchy over a face's vertices.
#include "hlod/parry/SphereHierarchy.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>
#include <queue>

namespace hlod {

namespace {

// A total order on positions along one axis: ties broken by the other coordinates, then by the
// vertex (only equal positions reach it), so that a split depends on the positions alone.
struct AlongAxis {
  std::span<const SphereVertex> vertices;
  int axis;
  bool operator()(std::uint32_t a, std::uint32_t b) const {
    const glm::dvec3& p = vertices[a].position;
    const glm::dvec3& q = vertices[b].position;
    if (p[axis] != q[axis]) return p[axis] < q[axis];
    for (int k = 0; k < 3; ++k)
      if (p[k] != q[k]) return p[k] < q[k];
    return a < b;
  }
};

SphereNode leafOf(const SphereVertex& v) {
  SphereNode n;
  n.centre = v.position;
  n.radius = v.radius;
  n.normal = v.normal;
  n.texCoord = v.texCoord;
  return n;
}

// The parent of nodes a and b: the average of their centres, a sphere holding both of theirs,
// the average normal and the cone that holds both cones.
SphereNode parentOf(const SphereNode& a, const SphereNode& b) {
  SphereNode p;
  p.centre = 0.5 * (a.centre + b.centre);
  p.radius = std::max(glm::length(a.centre - p.centre) + a.radius,
                      glm::length(b.centre - p.centre) + b.radius);
  const glm::vec3 sum = a.normal + b.normal;
  const float len = glm::length(sum);
  p.normal = len > 1e-6f && std::isfinite(len) ? sum / len : a.normal;
  double halfWidth = 0.0;
  for (const SphereNode* c : {&a, &b}) {
    const double angle = std::acos(std::clamp(double(glm::dot(p.normal, c->normal)), -1.0, 1.0));
    halfWidth = std::max(halfWidth, angle + std::acos(std::clamp(double(c->coneCos), -1.0, 1.0)));
  }
  p.coneCos = float(std::cos(std::min(halfWidth, M_PI)));
  p.texCoord = 0.5f * (a.texCoord + b.texCoord);
  return p;
}

// Splits ids (a range of one group's vertices) at the median along the longest axis of their
// box, recursively; returns the range's node. Depth log2 of the group's size.
std::uint32_t split(std::span<const SphereVertex> vertices, std::span<std::uint32_t> ids,
                    SphereHierarchy& h) {
  assert(!ids.empty());
  if (ids.size() == 1) return ids[0];
  glm::dvec3 lo = vertices[ids[0]].position, hi = lo;
  for (std::uint32_t v : ids) {
    lo = glm::min(lo, vertices[v].position);
    hi = glm::max(hi, vertices[v].position);
  }
  const glm::dvec3 extent = hi - lo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const std::size_t half = ids.size() / 2;
  std::nth_element(ids.begin(), ids.begin() + half, ids.end(), AlongAxis{vertices, axis});
  const std::uint32_t a = split(vertices, ids.subspan(0, half), h);
  const std::uint32_t b = split(vertices, ids.subspan(half), h);
  const auto p = std::uint32_t(h.nodes.size());
  h.nodes.push_back(parentOf(h.nodes[a], h.nodes[b]));
  h.nodes[p].child[0] = a;
  h.nodes[p].child[1] = b;
  h.nodes[a].parent = p;
  h.nodes[b].parent = p;
  return p;
}

}  // namespace

SphereHierarchy buildSphereHierarchy(std::span<const SphereVertex> vertices) {
  SphereHierarchy h;
  h.leafCount = vertices.size();
  h.nodes.reserve(2 * vertices.size());
  for (const SphereVertex& v : vertices) h.nodes.push_back(leafOf(v));
  // Groups in the order of their ids, so that the forest does not depend on a hash's order.
  std::map<std::uint32_t, std::vector<std::uint32_t>> groups;
  for (std::uint32_t v = 0; v < vertices.size(); ++v) {
    if (vertices[v].silhouette)
      h.roots.push_back(v);
    else
      groups[vertices[v].group].push_back(v);
  }
  for (auto& [group, ids] : groups) h.roots.push_back(split(vertices, ids, h));
  return h;
}

void mergeIntoCorners(SphereHierarchy& h,
                      std::span<const std::pair<std::uint32_t, std::uint32_t>> runIntoCorner) {
  assert(h.merges == 0);
  const std::size_t forestEnd = h.nodes.size();
  for (const auto& [run, corner] : runIntoCorner) {
    assert(corner < h.leafCount && h.nodes[run].parent == kNoSphere);
    std::uint32_t top = corner;
    while (h.nodes[top].parent != kNoSphere) top = h.nodes[top].parent;
    assert(top != run);
    const SphereNode& a = h.nodes[top];
    const SphereNode& b = h.nodes[run];
    SphereNode p = parentOf(a, b);
    p.centre = a.centre;
    p.radius = std::max(a.radius, glm::length(b.centre - a.centre) + b.radius);
    p.texCoord = a.texCoord;
    p.child[0] = top;
    p.child[1] = run;
    const auto id = std::uint32_t(h.nodes.size());
    h.nodes.push_back(p);
    h.nodes[top].parent = id;
    h.nodes[run].parent = id;
  }
  std::vector<std::uint32_t> roots;
  for (std::uint32_t r : h.roots)
    if (h.nodes[r].parent == kNoSphere) roots.push_back(r);
  h.merges = h.nodes.size() - forestEnd;
  for (std::size_t n = forestEnd; n < h.nodes.size(); ++n)
    if (h.nodes[n].parent == kNoSphere) roots.push_back(std::uint32_t(n));
  h.roots = std::move(roots);
}

std::vector<std::uint32_t> sphereCut(const SphereHierarchy& hierarchy, std::size_t count) {
  const auto larger = [&](std::uint32_t a, std::uint32_t b) {
    const double ra = hierarchy.nodes[a].radius, rb = hierarchy.nodes[b].radius;
    return ra != rb ? ra < rb : a > b;
  };
  std::priority_queue<std::uint32_t, std::vector<std::uint32_t>, decltype(larger)> open(larger);
  std::vector<std::uint32_t> cut;
  for (std::uint32_t r : hierarchy.roots)
    (hierarchy.nodes[r].isLeaf() ? cut.push_back(r) : open.push(r));
  while (!open.empty() && cut.size() + open.size() < count) {
    const std::uint32_t n = open.top();
    open.pop();
    for (std::uint32_t c : hierarchy.nodes[n].child)
      (hierarchy.nodes[c].isLeaf() ? cut.push_back(c) : open.push(c));
  }
  for (; !open.empty(); open.pop()) cut.push_back(open.top());
  std::sort(cut.begin(), cut.end());
  return cut;
}

}  // namespace hlod
