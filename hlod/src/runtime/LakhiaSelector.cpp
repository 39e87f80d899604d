// Lakhia III-C front selection. See hlod/runtime/LakhiaSelector.h and the constants in
// LakhiaParams.
#include "hlod/runtime/LakhiaSelector.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace hlod {

namespace {

double finiteOr(double v, double fallback) {
  return std::isfinite(v) ? v : fallback;
}

glm::dvec3 finiteOr(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) ? v : glm::dvec3(0.0);
}

}  // namespace

PriorityModel::PriorityModel(const View& view, const LakhiaParams& params)
    : params_(params),
      frustum_(view.camera.frustum()),
      lookAhead_(view.camera.position + finiteOr(params.c_velocity, 0.0) * finiteOr(view.velocity)),
      view_(view.camera.forward()),
      pixelsPerUnitAt1_(view.camera.pixelsPerUnit(1.0, view.viewportHeight)) {}

NodePriority PriorityModel::evaluate(const NodeInfo& node, double errorRemoved) const {
  NodePriority p;
  const double outside = frustum_.distanceOutside(node.bounds);
  p.visible = outside <= 0.0;
  if (p.visible) {
    p.frustumVis = 1.0;
  } else {
    const double falloff = params_.c_visFalloff * glm::length(node.bounds.size());
    p.frustumVis = falloff > 0.0 ? std::max(0.0, 1.0 - outside / falloff) : 0.0;
  }
  p.vis = 1.0 + params_.c_vis * p.frustumVis;
  const double facing = -glm::dot(view_, glm::dvec3(node.avgNormal));
  p.foreshorten = std::max(0.0, 1.0 + finiteOr(facing, 0.0) * params_.c_fore);
  const double minDistance = params_.c_minDistance > 0.0 ? params_.c_minDistance : 1e-6;
  p.distance = std::max(minDistance, distanceToBox(lookAhead_, node.bounds));
  if (errorRemoved > 0.0) {
    const double errorPx = errorRemoved * pixelsPerUnitAt1_ / std::max(p.distance, 1e-9);
    p.benefit = finiteOr(errorPx * p.vis * p.foreshorten, 0.0);
  } else {
    const double staticBenefit = std::max(0.0, finiteOr(node.staticBenefit, 0.0));
    p.benefit = finiteOr(staticBenefit * p.vis * p.foreshorten / (p.distance * p.distance), 0.0);
  }
  const double minCost = params_.c_minCost > 0.0 ? params_.c_minCost : 1e-9;
  const double cost = std::isfinite(node.cost) ? std::max(node.cost, minCost) : minCost;
  p.priority = finiteOr(p.benefit / cost, 0.0);
  return p;
}

LakhiaSelector::LakhiaSelector(const Skeleton& skeleton, const SelectorParams& params)
    : Selector(skeleton, params),
      hyst_(skeleton.nodes.size(), 0.0),
      timeSlice_(skeleton.nodes.size(), 0.0),
      priority_(skeleton.nodes.size(), 0.0),
      visitFrame_(skeleton.nodes.size(), 0xffffffffu),
      leafCost_(skeleton.nodes.size(), 0.0),
      evaluatedFrame_(skeleton.nodes.size(), 0xffffffffu),
      visible_(skeleton.nodes.size(), 0),
      slicedFrame_(skeleton.nodes.size(), 0xffffffffu) {
  const auto& nodes = skeleton.nodes;
  errorsKnown_ = std::any_of(nodes.begin(), nodes.end(), [](const NodeInfo& n) {
    return n.childCount > 0 && n.geometricError > 0.0;
  });
  const double e = params_.lakhia.c_errorBenefit;
  errorBenefit_ =
      errorsKnown_ && (e < 0.0 ? skeleton.params.simplifier == kTilesetSimplifier : e > 0.0);
  // Bottom up (children follow their parents in the store): the cost of each subtree's leaves,
  // an exact node standing for its subtree.
  for (std::size_t i = nodes.size(); i-- > 0;) {
    if (nodes[i].childCount == 0 || exact(std::uint32_t(i)))
      leafCost_[i] = effectiveCost(std::uint32_t(i));
    const std::uint32_t parent = nodes[i].parent;
    if (parent < nodes.size() && parent < i) leafCost_[parent] += leafCost_[i];
  }
}

double LakhiaSelector::errorRemoved(std::uint32_t n) const {
  if (!errorBenefit_) return 0.0;
  const NodeInfo& info = skeleton_.nodes[n];
  if (info.geometricError > 0.0) return info.geometricError;
  return info.parent < skeleton_.nodes.size() ? skeleton_.nodes[info.parent].geometricError : 0.0;
}

double LakhiaSelector::timeNeeded(std::uint32_t node) const {
  return vTime() * effectiveCost(node);
}

void LakhiaSelector::updateHyst(std::uint32_t node) {
  const LakhiaParams& p = params_.lakhia;
  const double limit = std::max(0.0, p.c_hystLimit);
  // A node not traversed in the previous frame starts afresh (its old counter is stale).
  if (visitFrame_[node] != frame_ - 1) hyst_[node] = std::clamp(p.c_hystInitial, -limit, limit);
  visitFrame_[node] = frame_;
  // hyst_n <- hyst_n + (timeSlice_n - timeNeeded_n) / timeNeeded_n, clamped to +-c_hystLimit.
  // timeNeeded >= v_time * c_minCost > 0, so the urgency is finite.
  const double needed = timeNeeded(node);
  const double urgency = finiteOr((timeSlice_[node] - needed) / needed, 0.0);
  hyst_[node] = std::clamp(hyst_[node] + urgency, -limit, limit);
}

long long LakhiaSelector::sliceSiblings(const std::vector<std::uint32_t>& visibleSiblings,
                                        double shareTime) {
  // Eq. 4: timeSlice_n = shareTime_n * priority_n / sum over visible siblings of priority_i.
  // All priorities zero (no area, or all facing away with c_fore = 1): share equally.
  // Departure from eq. 4: every sibling first gets its own timeNeeded (it is drawn at least at
  // its own level, so a smaller slice is time it spends anyway), and eq. 4 shares only the rest,
  // shareTime - sum timeNeeded, by priority. The slices sum to shareTime (unless every subtree is
  // capped, below). With eq. 4 alone,
  // far nodes overspend their small slices while near nodes refine into the whole of theirs, and
  // the frame overshoots the budget. When even the needs do not fit, each gets shareTime in
  // proportion to its need (all equally short). Both forms are continuous in v_time, so frame-time
  // noise moves slices smoothly (no sibling jumps between the two cases).
  // The spare is capped per sibling at what its subtree can use at all (its leaves' need times
  // c_demandMargin: a leaf or a small subtree near the camera cannot spend more, and the margin
  // keeps the urgency of leaves positive so that they can still be refined into); what a cap
  // leaves over goes to the others by priority (water-filling, continuous in v_time).
  double needSum = 0.0;
  for (std::uint32_t n : visibleSiblings) needSum += timeNeeded(n);
  const double spare = shareTime - needSum;
  if (spare <= 0.0) {
    for (std::uint32_t n : visibleSiblings)
      timeSlice_[n] = needSum > 0.0 ? shareTime * timeNeeded(n) / needSum : 0.0;
  } else {
    for (std::uint32_t n : visibleSiblings) timeSlice_[n] = timeNeeded(n);
    capped_.assign(visibleSiblings.size(), 0);
    double left = spare;
    for (bool changed = true; changed && left > 0.0;) {
      changed = false;
      double prioritySum = 0.0;
      std::size_t open = 0;
      for (std::size_t i = 0; i < visibleSiblings.size(); ++i)
        if (!capped_[i]) prioritySum += priority_[visibleSiblings[i]], ++open;
      if (open == 0) break;
      const bool byPriority = prioritySum > 0.0 && std::isfinite(prioritySum);
      for (std::size_t i = 0; i < visibleSiblings.size(); ++i) {
        if (capped_[i]) continue;
        const std::uint32_t n = visibleSiblings[i];
        const double share = byPriority ? left * priority_[n] / prioritySum : left / double(open);
        const double room =
            vTime() * leafCost_[n] * std::max(1.0, params_.lakhia.c_demandMargin) - timeNeeded(n);
        if (share >= room) {
          timeSlice_[n] = timeNeeded(n) + std::max(0.0, room);
          left -= std::max(0.0, room);
          capped_[i] = 1;
          changed = true;
        }
      }
      if (!changed) {
        for (std::size_t i = 0; i < visibleSiblings.size(); ++i) {
          if (capped_[i]) continue;
          const std::uint32_t n = visibleSiblings[i];
          timeSlice_[n] = timeNeeded(n) +
                          (byPriority ? left * priority_[n] / prioritySum : left / double(open));
        }
      }
    }
  }
  for (std::uint32_t n : visibleSiblings) slicedFrame_[n] = frame_;
  long long cumHyst = 0;
  const double hystSwitch = std::max(1e-9, params_.lakhia.c_hystSwitch);
  for (std::uint32_t n : visibleSiblings) {
    updateHyst(n);
    // cumHyst = sum over siblings of trunc(hyst_i / c_hystSwitch).
    cumHyst += static_cast<long long>(std::trunc(hyst_[n] / hystSwitch));
  }
  return cumHyst;
}

Selection LakhiaSelector::select(const View& view, const Residency& residency) {
  Selection s = beginFrame(view);
  const PriorityModel model(view, params_.lakhia);
  const auto& nodes = skeleton_.nodes;

  // Evaluates priority_ for a node and lists it for the loader; returns its visibility. Once per
  // frame: the budget fill asks again about children the walk already visited.
  auto visit = [&](std::uint32_t n) {
    if (evaluatedFrame_[n] == frame_) return visible_[n] != 0;
    evaluatedFrame_[n] = frame_;
    const NodePriority np = model.evaluate(nodes[n], errorRemoved(n));
    priority_[n] = np.priority;
    visible_[n] = np.visible;
    timeSlice_[n] = 0.0;  // invisible nodes get no share (sib() holds visible nodes only)
    s.loadPriorities.push_back({n, np.priority});
    return np.visible;
  };

  // Level 0: the visible hlod_0 nodes share c_targetTime: what is left of it for the drawing,
  // times c_aim.
  const double aim = params_.lakhia.c_aim;
  aimMs_ = s.drawBudgetMs * std::clamp(finiteOr(aim, 1.0), 0.1, 1.0);
  std::vector<std::uint32_t> visible;
  for (std::uint32_t r : candidateRoots(view, s)) {
    if (r < nodes.size() && visit(r) && !occludedNow(r, s)) visible.push_back(r);
  }
  sliceSiblings(visible, aimMs_);

  // Breadth-first: the visible children replace a node when their cumHyst allows it.
  walkFront(
      visible, residency, s, [](std::uint32_t) { return true; }, visit,
      [&](std::uint32_t n, const std::vector<std::uint32_t>& children) {
        if (exact(n)) return false;
        // shareTime of the children is the parent's timeSlice.
        const long long cumHyst = sliceSiblings(children, timeSlice_[n]);
        // Parent drawn when cumHyst < 0 (paper); refining anew needs cumHyst >= c_hystRefine.
        const long long threshold =
            refinedLastFrame(n) ? 0 : std::max(0LL, params_.lakhia.c_hystRefine);
        return cumHyst >= threshold;
      });
  fillBudget(s, residency, visit);
  shedBudget(s);
  // Parry's arrays: a node whose slice buys less than its whole is drawn with what it buys
  // (nodes the budget fill added fit whole; they were not sliced).
  planDraws(view, s, [&](std::uint32_t n) { return trianglesBought(n); });
  return s;
}

std::uint32_t LakhiaSelector::trianglesBought(std::uint32_t n) const {
  const NodeInfo& info = skeleton_.nodes[n];
  if (!params_.progressive || !info.progressive() || slicedFrame_[n] != frame_) return info.numTri;
  const double need = timeNeeded(n);
  if (!(timeSlice_[n] < need)) return info.numTri;
  // In steps of 1/kProgressiveSteps of the node's range, so that a slice that moves with
  // frame-time noise does not rebuild the node's index buffer every frame.
  const double range = double(info.numTri - info.minTri);
  const double step = std::max(1.0, range / kProgressiveSteps);
  const double bought = double(info.numTri) * std::max(0.0, timeSlice_[n]) / need;
  const double steps = std::round(std::max(0.0, bought - info.minTri) / step);
  return std::uint32_t(std::min<double>(info.numTri, info.minTri + steps * step));
}

void LakhiaSelector::shedBudget(Selection& s) {
  const double limit = aimMs_ * (1.0 + std::max(0.0, finiteOr(params_.lakhia.c_shed, 0.25)));
  const double v = vTime();
  if (!(v * s.estimatedCost > limit)) return;
  const auto& nodes = skeleton_.nodes;
  // A group can go back to its parent when none of its children was refined further.
  auto collapsible = [&](std::uint32_t p) {
    if (p >= nodes.size() || !refinedThisFrame(p)) return false;
    for (std::uint32_t c = nodes[p].firstChild; c < nodes[p].firstChild + nodes[p].childCount; ++c)
      if (refinedThisFrame(c)) return false;
    return true;
  };
  // Lowest priority first: the detail that buys the least goes first.
  std::vector<std::pair<double, std::uint32_t>> heap;
  auto push = [&](std::uint32_t p) {
    heap.emplace_back(-priority_[p], p);
    std::push_heap(heap.begin(), heap.end());
  };
  std::vector<std::uint8_t> queued(nodes.size(), 0);
  for (std::uint32_t n : s.front) {
    const std::uint32_t p = nodes[n].parent;
    if (p != kNoNode && !queued[p] && collapsible(p)) queued[p] = 1, push(p);
  }
  while (!heap.empty() && v * s.estimatedCost > aimMs_) {
    std::pop_heap(heap.begin(), heap.end());
    const std::uint32_t p = heap.back().second;
    heap.pop_back();
    if (!collapsible(p)) continue;
    replaceByParent(p, s);
    const std::uint32_t up = nodes[p].parent;
    if (up != kNoNode && !queued[up] && collapsible(up)) queued[up] = 1, push(up);
  }
  finishFrame(s);
}

template <class Visit>
void LakhiaSelector::fillBudget(Selection& s, const Residency& residency, Visit&& visit) {
  // Addition: the time the slices left unused. Each group decides with its own slice, and a
  // slice that cannot pay for a whole level of refinement (children cost about c_levelFactor
  // times their parent) is lost; summed over a city seen from above, with many blocks of equal
  // priority, that is a third of the budget. The rest of c_targetTime is spent here on further
  // refinements in priority order, as long as each fits whole. Hysteresis on the frame's total:
  // a node refined last frame stays refined while the total is within (1 + c_fillKeep) of the
  // aim by the steady v_time and (1 + c_fillFast) by the fast one; new refinements are made only
  // below (1 - c_fillAdd). Kept and new refinements are taken in one priority order: were the
  // kept ones taken first, a front chosen at one viewpoint would hold the budget while the
  // camera moves on, and nothing the new view needs more could replace it.
  const LakhiaParams& p = params_.lakhia;
  const double keepLimit = aimMs_ * (1.0 + std::clamp(finiteOr(p.c_fillKeep, 0.05), 0.0, 1.0));
  const double fastLimit = aimMs_ * (1.0 + std::clamp(finiteOr(p.c_fillFast, 0.1), 0.0, 1.0));
  const double addLimit = aimMs_ * (1.0 - std::clamp(finiteOr(p.c_fillAdd, 0.05), 0.0, 0.9));
  // New refinements are judged by the larger of v_time and its steadier twin, so that noise
  // does not add what it would later take back.
  const double vFast = vTime(), vSteady = vTimeSteady(), vAdd = std::max(vFast, vSteady);
  // Kept: within keepLimit by the steady v_time and within fastLimit by the fast one.
  auto keeps = [&](double c) { return vSteady * c <= keepLimit && vFast * c <= fastLimit; };
  double cost = s.estimatedCost;  // the drawing's part of the frame, in cost units
  if (!keeps(cost) || !std::isfinite(cost)) return;
  const auto& nodes = skeleton_.nodes;
  std::vector<std::pair<double, std::uint32_t>> heap;
  auto push = [&](std::uint32_t n) {
    if (nodes[n].childCount > 0 && !exact(n))
      heap.emplace_back(priority_[n], n), std::push_heap(heap.begin(), heap.end());
  };
  for (std::uint32_t n : s.front) push(n);
  std::vector<std::uint32_t> children;
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end());
    const std::uint32_t n = heap.back().second;
    heap.pop_back();
    const NodeInfo& info = nodes[n];
    // A decoded skeleton keeps every child range inside the nodes (decodeSkeleton).
    assert(info.firstChild < nodes.size() && info.childCount <= nodes.size() - info.firstChild);
    children.clear();
    double childCost = 0.0;
    bool resident = true;
    for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c) {
      if (!visit(c) || fullyFogged(c) || occludedNow(c, s)) continue;
      children.push_back(c);
      childCost += effectiveCost(c);
      resident = resident && residency.isResident(c);
    }
    if (!resident) {
      for (std::uint32_t c : children)
        if (!residency.isResident(c)) s.notResident.push_back(c);
      continue;
    }
    const double step = std::max(0.0, childCost - effectiveCost(n));
    // Inside the band [addLimit, keepLimit] nothing changes.
    const bool kept = refinedLastFrame(n);
    if (kept ? !keeps(cost + step) : vAdd * (cost + step) > addLimit) continue;
    cost += step;
    replaceByChildren(n, children, s);
    for (std::uint32_t c : children) push(c);
  }
  finishFrame(s);
}

}  // namespace hlod
