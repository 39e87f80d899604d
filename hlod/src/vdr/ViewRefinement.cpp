// Per-frame refinement of the active front (Manocha sec. 5.1; Hoppe 1997 for forced splits).
// See hlod/vdr/ViewRefinement.h.
#include "hlod/vdr/ViewRefinement.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <vector>

namespace hlod::vdr {

ErrorProjection ErrorProjection::of(const Camera& camera, int viewportHeight) {
  ErrorProjection p;
  p.eye = camera.position;
  p.pixelsPerUnit = camera.pixelsPerUnit(1.0, viewportHeight);
  p.frustum = camera.frustum();
  return p;
}

double ErrorProjection::operator()(const VertexHierarchy& h, std::uint32_t v) const {
  const double e = h.error[v];
  if (!(e > 0.0)) return 0.0;
  if (!perspective) return e * pixelsPerUnit;
  const glm::dvec3 p = h.position(v);
  const double r = h.radius[v];
  if (frustum)
    for (const Plane& plane : frustum->planes)
      if (plane.signedDistance(p) < -r) return 0.0;
  const double d = std::max(minDistance, glm::length(p - eye) - r);
  return e * pixelsPerUnit / d;
}

namespace {

// Splits v, splitting first the coarser neighbours its neighbourhood test names (recursively:
// each of them was made after the vertex that waits on it, so this ends). False when v could not
// be split. Every vertex split is appended to `split`.
bool forceSplit(ActiveMesh& mesh, std::uint32_t v, RefineCounters& counters,
                RefineObserver* observer, std::vector<std::uint32_t>& split) {
  constexpr std::size_t kMaxSteps = 1u << 16;
  std::vector<std::uint32_t> stack{v};
  for (std::size_t step = 0; !stack.empty() && step < kMaxSteps; ++step) {
    const std::uint32_t x = stack.back();
    if (!mesh.isActive(x)) {
      stack.pop_back();
      continue;
    }
    if (mesh.canSplit(x)) {
      mesh.split(x);
      split.push_back(x);
      stack.pop_back();
      ++counters.splits;
      if (x != v) ++counters.forcedSplits;
      if (observer) observer->split(x);
      continue;
    }
    const std::vector<std::uint32_t> blockers = mesh.coarserNeighbours(x);
    if (blockers.empty()) break;
    stack.insert(stack.end(), blockers.begin(), blockers.end());
  }
  return !mesh.isActive(v);
}

}  // namespace

RefineCounters refineToBound(ActiveMesh& mesh, std::span<const std::uint32_t> vertices,
                             const ErrorProjection& projection, double bound,
                             RefineObserver* observer) {
  const VertexHierarchy& h = mesh.hierarchy();
  RefineCounters counters;
  // Coarsening: sibling pairs whose parent meets the bound, in build order, then upwards.
  std::priority_queue<std::uint32_t, std::vector<std::uint32_t>, std::greater<>> parents;
  for (std::uint32_t v : vertices)
    if (v < h.vertexCount() && mesh.isActive(v) && h.parent[v] != kNone) parents.push(h.parent[v]);
  std::uint32_t last = kNone;
  while (!parents.empty()) {
    const std::uint32_t p = parents.top();
    parents.pop();
    if (p == last) continue;
    last = p;
    if (mesh.isActive(p) || !mesh.isActive(h.kept(p)) || !mesh.isActive(h.removed(p))) continue;
    if (projection(h, p) > bound || !mesh.canCollapse(p)) continue;
    mesh.collapse(p);
    ++counters.collapses;
    if (observer) observer->collapsed(p);
    if (h.parent[p] != kNone) parents.push(h.parent[p]);
  }
  // Refinement: the front vertices over the bound, largest projected error first.
  std::priority_queue<std::pair<double, std::uint32_t>> over;
  for (std::uint32_t v : vertices) {
    if (v >= h.vertexCount() || !mesh.isActive(v) || h.isLeaf(v)) continue;
    if (const double e = projection(h, v); e > bound) over.push({e, v});
  }
  std::vector<std::uint32_t> split;
  while (!over.empty()) {
    const std::uint32_t v = over.top().second;
    over.pop();
    if (!mesh.isActive(v)) continue;
    split.clear();
    forceSplit(mesh, v, counters, observer, split);
    // Recursively: the children of every vertex split (forced ones too) that are still over.
    for (std::uint32_t x : split)
      for (std::uint32_t c : {h.kept(x), h.removed(x)})
        if (!h.isLeaf(c) && mesh.isActive(c))
          if (const double e = projection(h, c); e > bound) over.push({e, c});
  }
  return counters;
}

}  // namespace hlod::vdr
