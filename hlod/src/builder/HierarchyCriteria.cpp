// The criteria of Manocha sec. 2.1.1, measured (hlod/builder/HierarchyCriteria.h).
#include "hlod/builder/HierarchyCriteria.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace hlod {

namespace {

double volume(const Aabb& b) {
  if (b.empty()) return 0.0;
  const glm::dvec3 s = b.size();
  return s.x * s.y * s.z;
}

Aabb padded(const Aabb& b, double pad) {
  Aabb out = b;
  if (out.empty()) return out;
  out.min -= glm::dvec3(pad);
  out.max += glm::dvec3(pad);
  return out;
}

Spread3 spreadOf(std::vector<double> v) {
  Spread3 s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.min = v.front();
  s.median = v[(v.size() - 1) / 2];
  s.max = v.back();
  return s;
}

}  // namespace

double overlapVolume(const Aabb& a, const Aabb& b) {
  if (a.empty() || b.empty()) return 0.0;
  const glm::dvec3 lo = glm::max(a.min, b.min), hi = glm::min(a.max, b.max);
  if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z)) return 0.0;
  return (hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z);
}

double unionVolume(const std::vector<Aabb>& boxes) {
  std::vector<double> cuts[3];
  for (const Aabb& b : boxes) {
    if (b.empty()) continue;
    for (int a = 0; a < 3; ++a) {
      cuts[a].push_back(b.min[a]);
      cuts[a].push_back(b.max[a]);
    }
  }
  for (auto& c : cuts) {
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
  }
  // Each cell of the grid the faces make is inside a box or outside all.
  double sum = 0.0;
  for (std::size_t i = 0; i + 1 < cuts[0].size(); ++i)
    for (std::size_t j = 0; j + 1 < cuts[1].size(); ++j)
      for (std::size_t k = 0; k + 1 < cuts[2].size(); ++k) {
        const glm::dvec3 mid(0.5 * (cuts[0][i] + cuts[0][i + 1]),
                             0.5 * (cuts[1][j] + cuts[1][j + 1]),
                             0.5 * (cuts[2][k] + cuts[2][k + 1]));
        const bool covered = std::any_of(boxes.begin(), boxes.end(), [&](const Aabb& b) {
          return !b.empty() && glm::all(glm::greaterThanEqual(mid, b.min)) &&
                 glm::all(glm::lessThanEqual(mid, b.max));
        });
        if (covered)
          sum += (cuts[0][i + 1] - cuts[0][i]) * (cuts[1][j + 1] - cuts[1][j]) *
                 (cuts[2][k + 1] - cuts[2][k]);
      }
  return sum;
}

double defaultPad(const HierarchyShape& shape) {
  Aabb scene;
  for (const HierarchyNode& n : shape.nodes) scene.extend(n.box);
  return 1e-3 * glm::length(scene.size());
}

HierarchyFigures measureHierarchy(const HierarchyShape& shape, double pad) {
  HierarchyFigures f;
  const auto& nodes = shape.nodes;
  f.nodes = nodes.size();
  if (nodes.empty()) return f;
  Aabb scene;
  std::vector<std::uint32_t> roots;
  for (std::uint32_t i = 0; i < nodes.size(); ++i) {
    scene.extend(nodes[i].box);
    if (nodes[i].parent == 0xffffffffu) roots.push_back(i);
  }
  f.roots = roots.size();
  const double sceneDiagonal = glm::length(scene.size());
  // Depth: parents come first, so a node's depth is known before its children's.
  std::vector<std::uint32_t> depth(nodes.size(), 0);
  std::vector<double> leafTriangles, leafDiagonal;
  double depthSum = 0.0, fillSum = 0.0, overlapSum = 0.0;
  std::size_t fillNodes = 0, overlapNodes = 0, pairs = 0, overlapping = 0;
  f.minLeafDepth = 0xffffffffu;
  // Sibling overlap among `children` (indices), over the volume of `parentBox`.
  const auto siblings = [&](const std::vector<std::uint32_t>& children, const Aabb& parentBox) {
    if (children.size() < 2) return;
    double shared = 0.0;
    for (std::size_t a = 0; a < children.size(); ++a)
      for (std::size_t b = a + 1; b < children.size(); ++b) {
        const double v =
            overlapVolume(padded(nodes[children[a]].box, pad), padded(nodes[children[b]].box, pad));
        shared += v;
        ++pairs;
        overlapping += v > 0.0;
      }
    const double whole = volume(padded(parentBox, pad));
    overlapSum += whole > 0.0 ? shared / whole : 0.0;
    ++overlapNodes;
  };
  siblings(roots, scene);
  for (std::uint32_t i = 0; i < nodes.size(); ++i) {
    const HierarchyNode& n = nodes[i];
    if (n.parent != 0xffffffffu) {
      assert(n.parent < i);
      depth[i] = depth[n.parent] + 1;
    }
    if (n.childCount == 0) {
      ++f.leaves;
      f.depth = std::max(f.depth, depth[i]);
      f.minLeafDepth = std::min(f.minLeafDepth, depth[i]);
      depthSum += depth[i];
      leafTriangles.push_back(double(n.triangles));
      leafDiagonal.push_back(sceneDiagonal > 0.0 ? glm::length(n.box.size()) / sceneDiagonal : 0.0);
      continue;
    }
    assert(n.firstChild > i && n.firstChild + n.childCount <= nodes.size());
    std::vector<std::uint32_t> children(n.childCount);
    for (std::uint32_t c = 0; c < n.childCount; ++c) children[c] = n.firstChild + c;
    siblings(children, n.box);
    if (n.childCount <= kMaxFillChildren) {
      std::vector<Aabb> boxes;
      for (std::uint32_t c : children) boxes.push_back(padded(nodes[c].box, pad));
      const double whole = volume(padded(n.box, pad));
      if (whole > 0.0) {
        fillSum += std::min(1.0, unionVolume(boxes) / whole);
        ++fillNodes;
      }
    }
  }
  if (f.leaves == 0) f.minLeafDepth = 0;
  f.meanLeafDepth = f.leaves ? depthSum / double(f.leaves) : 0.0;
  f.balance = f.depth > 0 ? double(f.minLeafDepth) / double(f.depth) : 1.0;
  f.innerFill = fillNodes ? fillSum / double(fillNodes) : 1.0;
  f.siblingOverlap = overlapNodes ? overlapSum / double(overlapNodes) : 0.0;
  f.overlappingPairs = pairs ? double(overlapping) / double(pairs) : 0.0;
  std::size_t objects = 0, cut = 0;
  double spread = 0.0;
  for (std::uint32_t l : shape.leavesPerObject) {
    if (l == 0) continue;
    ++objects;
    spread += l;
    cut += l > 1;
  }
  f.leavesPerObject = objects ? spread / double(objects) : 1.0;
  f.objectsCut = objects ? double(cut) / double(objects) : 0.0;
  f.leafTriangles = spreadOf(std::move(leafTriangles));
  f.leafDiagonal = spreadOf(std::move(leafDiagonal));
  return f;
}

}  // namespace hlod
