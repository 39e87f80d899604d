// Funkhouser & Sequin, "Adaptive display algorithm for interactive frame rates during
// visualization of complex virtual environments" (SIGGRAPH 93), greedy benefit/cost variant on
// the HLOD tree, as described in hlod/runtime/FsSelector.h.
#include "hlod/runtime/FsSelector.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <queue>

#include "hlod/runtime/LakhiaSelector.h"

namespace hlod {

FsSelector::FsSelector(const Skeleton& skeleton, const SelectorParams& params)
    : Selector(skeleton, params),
      benefit_(skeleton.nodes.size(), 0.0),
      visible_(skeleton.nodes.size(), 0),
      drawn_(skeleton.nodes.size(), 0) {}

Selection FsSelector::select(const View& view, const Residency& residency) {
  Selection s = beginFrame(view);
  const PriorityModel model(view, params_.lakhia);
  const auto& nodes = skeleton_.nodes;
  const double vTime = s.vTime;
  const double budget = s.drawBudgetMs;

  struct Candidate {
    double value;  // added benefit per added cost
    std::uint32_t node;
    bool operator<(const Candidate& o) const {
      return value < o.value || (value == o.value && node > o.node);
    }
  };
  std::priority_queue<Candidate> heap;
  std::vector<std::uint32_t> drawn;  // the front so far (entries refined later are skipped)
  std::vector<std::uint8_t>& isDrawn = drawn_;  // all 0 between frames
  std::vector<double>& benefitOf = benefit_;    // written by visit() before any read
  std::vector<std::uint8_t>& visibleOf = visible_;
  double cost = 0.0;

  auto visit = [&](std::uint32_t n) {
    const NodePriority np = model.evaluate(nodes[n]);
    benefitOf[n] = np.benefit;
    visibleOf[n] = np.visible && !occludedNow(n, s) ? 1 : 0;
    s.loadPriorities.push_back({n, np.priority});
  };
  auto hasChildren = [&](const NodeInfo& info) {
    assert(info.childCount == 0 ||
           (info.firstChild < nodes.size() && info.childCount <= nodes.size() - info.firstChild));
    return info.childCount > 0;
  };
  // Evaluates the children of a drawn node and queues its refinement.
  auto offer = [&](std::uint32_t n) {
    const NodeInfo& info = nodes[n];
    if (!hasChildren(info)) return;
    double addedBenefit = -benefitOf[n];
    double addedCost = -effectiveCost(n);
    const std::size_t hiddenBefore = s.occluded.size();
    bool childInView = false;
    for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c) {
      visit(c);
      if (!visibleOf[c]) continue;
      childInView = true;
      addedBenefit += benefitOf[c];
      addedCost += effectiveCost(c);
    }
    // Every child in view is hidden: so is the node's own surface, which approximates theirs.
    if (!childInView && s.occluded.size() > hiddenBefore) {
      isDrawn[n] = 0;
      cost -= effectiveCost(n);
      return;
    }
    double value;
    if (addedCost <= 0.0) {
      value = std::numeric_limits<double>::max();  // free refinement: take it first
    } else if (addedBenefit <= 0.0) {
      return;  // costs time and gains nothing
    } else {
      value = addedBenefit / addedCost;
    }
    if (std::isfinite(value)) heap.push({value, n});
  };

  for (std::uint32_t r : candidateRoots(view, s)) {
    if (r >= nodes.size()) continue;
    visit(r);
    if (!visibleOf[r]) continue;
    isDrawn[r] = 1;
    drawn.push_back(r);
    cost += effectiveCost(r);
  }
  for (std::size_t i = 0; i < drawn.size(); ++i) offer(drawn[i]);

  while (!heap.empty()) {
    const std::uint32_t n = heap.top().node;
    heap.pop();
    const NodeInfo& info = nodes[n];
    double childCost = 0.0;
    bool allResident = true;
    for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c) {
      if (!visibleOf[c]) continue;
      childCost += effectiveCost(c);
      allResident = allResident && residency.isResident(c);
    }
    const double newCost = cost - effectiveCost(n) + childCost;
    if (vTime * newCost > budget && newCost > cost) continue;  // does not fit; try cheaper ones
    if (!allResident) {
      ++s.coarserBecauseNotResident;
      for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c)
        if (visibleOf[c] && !residency.isResident(c)) s.notResident.push_back(c);
      continue;
    }
    cost = newCost;
    isDrawn[n] = 0;
    markRefined(n, s);
    for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c) {
      if (!visibleOf[c]) continue;
      isDrawn[c] = 1;
      drawn.push_back(c);
      offer(c);
    }
  }
  for (std::uint32_t n : drawn) {
    if (isDrawn[n]) markDrawn(n, s);
    isDrawn[n] = 0;
  }
  planDraws(view, s);
  return s;
}

}  // namespace hlod
