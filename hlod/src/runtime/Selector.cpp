#include "hlod/runtime/Selector.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "hlod/runtime/FsSelector.h"
#include "hlod/runtime/FullSelector.h"
#include "hlod/runtime/LakhiaSelector.h"
#include "hlod/runtime/OcclusionCulling.h"
#include "hlod/runtime/SseSelector.h"

namespace hlod {

namespace {
constexpr double kMinVTime = 1e-12;
constexpr double kMaxVTime = 1e6;
}  // namespace

VTimeFeedback::VTimeFeedback(double initial, double gain, double maxRatio, double jumpRatio)
    : vTime_(kMinVTime),
      gain_(std::isfinite(gain) ? std::clamp(gain, 0.0, 1.0) : 0.2),
      maxRatio_(std::isfinite(maxRatio) && maxRatio > 1.0 ? maxRatio : 4.0),
      jumpRatio_(std::isfinite(jumpRatio) && jumpRatio > 1.0 ? jumpRatio : 0.0) {
  set(initial);
}

void VTimeFeedback::set(double vTime) {
  if (std::isfinite(vTime) && vTime > 0.0) vTime_ = std::clamp(vTime, kMinVTime, kMaxVTime);
  observedCount_ = 0;
}

void VTimeFeedback::update(double measuredMs, double drawnCost) {
  if (!(std::isfinite(measuredMs) && measuredMs > 0.0)) return;
  if (!(std::isfinite(drawnCost) && drawnCost > 0.0)) return;
  observed_[observedCount_++ % observed_.size()] = measuredMs / drawnCost;
  std::array<double, 3> last = observed_;
  const std::size_t n = std::min(observedCount_, last.size());
  std::sort(last.begin(), last.begin() + n);
  // The median of three; of two, the smaller (the newer frame must be confirmed to go up).
  const double k = n == 3 ? last[1] : last[0];
  const double off = k / vTime_;
  if (n == 3 && jumpRatio_ > 0.0 && (off > jumpRatio_ || off < 1.0 / jumpRatio_)) {
    // Three frames agree on a real change: follow it now.
    const double m = maxRatio_ * maxRatio_;
    vTime_ = std::clamp(vTime_ * std::clamp(off, 1.0 / m, m), kMinVTime, kMaxVTime);
    return;
  }
  const double ratio = std::clamp(off, 1.0 / maxRatio_, maxRatio_);
  vTime_ = std::clamp(vTime_ * std::pow(ratio, gain_), kMinVTime, kMaxVTime);
}

Selector::Selector(const Skeleton& skeleton, const SelectorParams& params)
    : skeleton_(skeleton),
      params_(params),
      feedback_(params.lakhia.vTimeInitial, params.lakhia.feedbackGain,
                params.lakhia.feedbackMaxRatio, params.lakhia.feedbackJumpRatio),
      steadyFeedback_(params.lakhia.vTimeInitial, params.lakhia.c_fillGain,
                      params.lakhia.feedbackMaxRatio, params.lakhia.feedbackJumpRatio),
      culling_(skeleton),
      drawnFrame_(skeleton.nodes.size(), kNever),
      drawnBefore_(skeleton.nodes.size(), kNever),
      refinedFrame_(skeleton.nodes.size(), kNever),
      refinedBefore_(skeleton.nodes.size(), kNever),
      occludedFrame_(skeleton.nodes.size(), kNever) {
  for (const NodeInfo& n : skeleton.nodes) maxLevel_ = std::max(maxLevel_, n.level);
}

void Selector::feedback(double measuredMs) {
  feedback_.update(measuredMs, lastEstimatedCost_);
  steadyFeedback_.update(measuredMs, lastEstimatedCost_);
}

double Selector::effectiveCost(std::uint32_t node) const {
  const double c = skeleton_.nodes[node].cost;
  const double minCost = params_.lakhia.c_minCost > 0.0 ? params_.lakhia.c_minCost : 1e-9;
  return std::isfinite(c) ? std::max(c, minCost) : minCost;
}

double Selector::drawCost(std::uint32_t node, const NodeDraw& d) const {
  const NodeInfo& n = skeleton_.nodes[node];
  const double minCost = params_.lakhia.c_minCost > 0.0 ? params_.lakhia.c_minCost : 1e-9;
  if (d.splats) return std::max(minCost, params_.c_splat * double(n.splatCount));
  if (d.triangles >= n.numTri || n.numTri == 0) return effectiveCost(node);
  // Eq. 1 is linear in the triangles: a share of them costs that share.
  return std::max(minCost, effectiveCost(node) * double(d.triangles) / double(n.numTri));
}

Selection Selector::beginFrame(const View& view) {
  ++frame_;
  if (frame_ == kNever) frame_ = 1;  // wrap-around after 4 billion frames: forget the history
  Selection s;
  s.targetMs = params_.lakhia.c_targetTime;
  s.spentMs = std::isfinite(view.spentMs) ? std::max(0.0, view.spentMs) : 0.0;
  // FrameDriver gives a finite share; anything else would stall or explode every estimate.
  assert(std::isfinite(view.frontDraws) && view.frontDraws >= 1.0);
  s.frontDraws = view.frontDraws;
  s.drawBudgetMs =
      std::isfinite(s.targetMs) ? std::max(0.0, s.targetMs - s.spentMs) / s.frontDraws : 0.0;
  s.vTime = feedback_.vTime();
  fogEye_ = view.camera.position;
  occlusion_ = view.occlusion;
  fogCullDistance_ = view.fogCullDistance > 0.0 ? view.fogCullDistance : 0.0;
  s.nodesDrawnPerLevel.assign(skeleton_.nodes.empty() ? 0 : maxLevel_ + 1, 0);
  return s;
}

const std::vector<std::uint32_t>& Selector::candidateRoots(const View& view, Selection& s) {
  if (!params_.quadtreeCulling) return skeleton_.roots;
  s.quadtree =
      culling_.candidateRoots(view.camera.frustum(), params_.lakhia.c_visFalloff, candidates_);
  return candidates_;
}

bool Selector::fullyFogged(std::uint32_t node) const {
  return std::isfinite(fogCullDistance_) &&
         distanceToBox(fogEye_, skeleton_.nodes[node].bounds) > fogCullDistance_;
}

bool Selector::occludedNow(std::uint32_t node, Selection& s) {
  if (!occlusion_ || !occlusion_->occluded(node)) return false;
  if (occludedFrame_[node] != frame_) {
    occludedFrame_[node] = frame_;
    s.occluded.push_back(node);
    s.occludedTriangles += skeleton_.nodes[node].numTri;
  }
  return true;
}

void Selector::applyOcclusionToLoads(Selection& s) const {
  if (s.occluded.empty()) return;
  const double scale = std::clamp(params_.c_occludedLoad, 0.0, 1.0);
  for (LoadRequest& r : s.loadPriorities)
    if (occludedFrame_[r.node] == frame_) r.priority *= scale;
  // Detail of a node hidden only lately stays wanted (at its lowered priority), so that it is
  // still resident when the node comes back into view.
  const double keep = std::max(0.0, params_.c_occludedKeepFrames);
  const std::size_t listed = s.loadPriorities.size();
  for (std::size_t i = 0; i < listed; ++i) {
    const LoadRequest r = s.loadPriorities[i];
    if (occludedFrame_[r.node] != frame_ || refinedFrame_[r.node] == kNever ||
        double(frame_ - refinedFrame_[r.node]) > keep)
      continue;
    const NodeInfo& info = skeleton_.nodes[r.node];
    for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c)
      s.loadPriorities.push_back({c, r.priority});
  }
}

void Selector::markRefined(std::uint32_t node, Selection& s) {
  if (drawnFrame_[node] == frame_ - 1) ++s.upToggles;
  refinedBefore_[node] = refinedFrame_[node];
  refinedFrame_[node] = frame_;
}

void Selector::markDrawn(std::uint32_t node, Selection& s) {
  if (refinedFrame_[node] == frame_ - 1) ++s.downToggles;
  drawnBefore_[node] = drawnFrame_[node];
  drawnFrame_[node] = frame_;
  const NodeInfo& n = skeleton_.nodes[node];
  s.front.push_back(node);
  s.estimatedCost += effectiveCost(node);
  s.triangles += n.numTri;
  if (n.isCell())
    ++s.cellsDrawn;
  else if (n.level < s.nodesDrawnPerLevel.size())
    ++s.nodesDrawnPerLevel[n.level];
}

void Selector::replaceByChildren(std::uint32_t node, const std::vector<std::uint32_t>& children,
                                 Selection& s) {
  auto it = std::find(s.front.begin(), s.front.end(), node);
  if (it == s.front.end()) return;
  s.front.erase(it);
  // Undo markDrawn's counters, then count the node as refined and its children as drawn.
  if (refinedFrame_[node] == frame_ - 1) --s.downToggles;
  drawnFrame_[node] = drawnBefore_[node];
  const NodeInfo& n = skeleton_.nodes[node];
  s.estimatedCost -= effectiveCost(node);
  s.triangles -= n.numTri;
  if (n.isCell())
    --s.cellsDrawn;
  else if (n.level < s.nodesDrawnPerLevel.size())
    --s.nodesDrawnPerLevel[n.level];
  markRefined(node, s);
  for (std::uint32_t c : children) markDrawn(c, s);
}

void Selector::replaceByParent(std::uint32_t node, Selection& s) {
  assert(refinedFrame_[node] == frame_);
  const NodeInfo& info = skeleton_.nodes[node];
  const std::uint32_t first = info.firstChild, end = info.firstChild + info.childCount;
  // Undo the children's markDrawn and the node's markRefined, then draw the node.
  std::erase_if(s.front, [&](std::uint32_t n) {
    if (n < first || n >= end) return false;
    assert(refinedFrame_[n] != frame_);
    if (refinedFrame_[n] == frame_ - 1) --s.downToggles;
    drawnFrame_[n] = drawnBefore_[n];
    const NodeInfo& c = skeleton_.nodes[n];
    s.estimatedCost -= effectiveCost(n);
    s.triangles -= c.numTri;
    if (c.isCell())
      --s.cellsDrawn;
    else if (c.level < s.nodesDrawnPerLevel.size())
      --s.nodesDrawnPerLevel[c.level];
    return true;
  });
  if (drawnFrame_[node] == frame_ - 1) --s.upToggles;
  refinedFrame_[node] = refinedBefore_[node];
  markDrawn(node, s);
}

void Selector::finishFrame(Selection& s) {
  s.estimatedMs = s.spentMs + s.frontDraws * s.vTime * s.estimatedCost;
  lastEstimatedCost_ = s.estimatedCost;
}

Result<std::unique_ptr<Selector>> makeSelector(std::string_view name, const Skeleton& skeleton,
                                               const SelectorParams& params) {
  std::unique_ptr<Selector> s;
  if (name == "lakhia") {
    s = std::make_unique<LakhiaSelector>(skeleton, params);
  } else if (name == "sse") {
    s = std::make_unique<SseSelector>(skeleton, params);
  } else if (name == "fs") {
    s = std::make_unique<FsSelector>(skeleton, params);
  } else if (name == "full") {
    s = std::make_unique<FullSelector>(skeleton, params);
  } else if (name == "vdr") {
    // It refines the objects of a store's view-dependent section: a session makes it with them.
    return makeError(
        "the vdr selector is made with a store's view-dependent section (a session on a store "
        "built with --vdr), not from a skeleton");
  } else {
    return makeError("unknown selector '" + std::string(name) +
                     "' (known: lakhia, sse, fs, full, vdr)");
  }
  return s;
}

}  // namespace hlod
