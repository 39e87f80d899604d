// Culling from the block quadtree down (hlod/runtime/QuadtreeCulling.h).
#include "hlod/runtime/QuadtreeCulling.h"

#include <algorithm>
#include <cmath>

namespace hlod {

QuadtreeCulling::QuadtreeCulling(const Skeleton& skeleton)
    : skeleton_(skeleton), reach_(skeleton.quadtree.cells.size(), 0.0) {
  const BlockQuadtree& q = skeleton.quadtree;
  // Bottom up: children come after their parents.
  for (std::size_t i = q.cells.size(); i-- > 0;) {
    const QuadCell& c = q.cells[i];
    for (std::uint32_t k = c.firstBlock; k < c.firstBlock + c.blockCount; ++k)
      reach_[i] = std::max(reach_[i], glm::length(skeleton.nodes[q.blocks[k].root].bounds.size()));
    for (std::uint32_t k = c.firstChild; k < c.firstChild + c.childCount; ++k)
      reach_[i] = std::max(reach_[i], reach_[k]);
  }
}

QuadtreeWalk QuadtreeCulling::candidateRoots(const Frustum& frustum, double falloff,
                                             std::vector<std::uint32_t>& roots) const {
  QuadtreeWalk walk;
  const BlockQuadtree& q = skeleton_.quadtree;
  // Cell nodes cull their blocks themselves: a selector evaluates the cells top down.
  if (q.empty() || skeleton_.hasCells()) {
    roots = skeleton_.roots;
    return walk;
  }
  roots.clear();
  // std::max(0, NaN) is 0: then only cells outside the frustum at all are skipped, whose roots
  // evaluate with frustumVis 0 too (a NaN fall-off is never > 0).
  const double scale = std::max(0.0, falloff);
  std::vector<std::uint32_t> stack{0};
  while (!stack.empty()) {
    const std::uint32_t i = stack.back();
    stack.pop_back();
    const QuadCell& c = q.cells[i];
    ++walk.cellsVisited;
    if (frustum.distanceOutside(c.bounds) > scale * reach_[i]) {
      ++walk.cellsCulled;
      continue;
    }
    for (std::uint32_t k = c.firstBlock; k < c.firstBlock + c.blockCount; ++k)
      roots.push_back(q.blocks[k].root);
    for (std::uint32_t k = c.firstChild; k < c.firstChild + c.childCount; ++k) stack.push_back(k);
  }
  std::sort(roots.begin(), roots.end());
  return walk;
}

}  // namespace hlod
