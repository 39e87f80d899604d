#pragma once
// Front selection: which HLOD nodes to draw this frame, with load priorities for the loader and
// per-frame counters for the statistics of Lakhia sec. IV (levels drawn, toggles).
//
// One Selector per viewing session (it holds hysteresis counters, v_time and the last front).
// select() and feedback() run on the render thread; nothing here uses threads, so tests drive
// a selector frame by frame with a simulated frame time.
//
// Drive one frame:
//   Selection s = selector->select(view, residency);   // residency: what the renderer can draw
//   loader.setWanted(s.loadPriorities);                 // loader fetches what is missing
//   ... draw s.front, measure the frame time ...
//   selector->feedback(measuredMs);                      // v_time feedback loop
#include <algorithm>
#include <array>
#include <cassert>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "hlod/Result.h"
#include "hlod/runtime/Camera.h"
#include "hlod/runtime/QuadtreeCulling.h"
#include "hlod/store/Skeleton.h"

namespace hlod {

// Which nodes can be drawn now. Roots (hlod_0 nodes, or the top cell) must always answer true.
class Residency {
 public:
  virtual ~Residency() = default;
  virtual bool isResident(std::uint32_t node) const = 0;
};

// Everything resident: the reference case and most selector tests.
class AllResident final : public Residency {
 public:
  bool isResident(std::uint32_t) const override { return true; }
};

// A plain residency set owned by one thread, e.g. the render thread's "uploaded to the GPU" set
// kept up to date from Loader::drainEvents(). Unknown nodes are not resident.
class ResidencySet final : public Residency {
 public:
  explicit ResidencySet(std::size_t nodeCount = 0) : resident_(nodeCount, 0) {}
  void set(std::uint32_t node, bool resident) {
    if (node >= resident_.size()) resident_.resize(node + 1, 0);
    resident_[node] = resident ? 1 : 0;
  }
  bool isResident(std::uint32_t node) const override {
    return node < resident_.size() && resident_[node] != 0;
  }

 private:
  std::vector<std::uint8_t> resident_;
};

// A node the selector looked at, with its priority (higher = more important). Resident nodes are
// listed too, so the loader can unload the lowest first.
struct LoadRequest {
  std::uint32_t node = kNoNode;
  double priority = 0.0;
};

// What to draw of a node of the front.
struct NodeDraw {
  std::uint32_t triangles = 0;  // numTri (whole), or fewer from its progression; 0 with splats
  bool splats = false;          // drawn as its splats
};

struct Selection {
  std::vector<std::uint32_t> front;  // nodes to draw, each resident
  double estimatedMs =
      0.0;  // spentMs + frontDraws * sum of timeNeeded (v_time * cost of the front)
  double estimatedCost = 0.0;  // sum of cost (eq. 1) of the front
  double targetMs = 0.0;       // the budget this frame was selected for
  double spentMs = 0.0;        // of it, spent before drawing (View::spentMs)
  double drawBudgetMs = 0.0;   // (targetMs - spentMs) / frontDraws, at least 0: the geometry pass's
  double frontDraws = 1.0;  // View::frontDraws: the passes that draw the front, in geometry passes
  double vTime = 0.0;       // v_time used (ms per unit of cost)
  std::vector<LoadRequest> loadPriorities;  // every visited node, resident or not
  std::uint32_t upToggles = 0;    // nodes drawn last frame, replaced by their children now
  std::uint32_t downToggles = 0;  // nodes whose children were drawn last frame, drawn now
  std::uint32_t fogCulled = 0;    // visible nodes left out: wholly beyond View::fogCullDistance
  std::uint32_t coarserBecauseNotResident = 0;  // drawn coarser: a visible child not resident
  std::vector<std::uint32_t> notResident;  // those children: what the frame waited to refine into
  // Occlusion culling (View::occlusion): the nodes in the frustum that the walk left out, each
  // with its subtree, because a query found its box hidden. Their boxes are queried again.
  std::vector<std::uint32_t> occluded;
  std::uint64_t occludedTriangles = 0;  // the occluded nodes' own triangles (at their level)
  std::vector<std::uint32_t> nodesDrawnPerLevel;  // index = level d of hlod_d (blocks' nodes)
  std::uint32_t cellsDrawn = 0;                   // cell nodes drawn (Skeleton.h)
  std::uint64_t triangles = 0;                    // triangles drawn (draws)
  // Per node of front, in its order (Selector::planDraws): whole, fewer triangles, or splats.
  std::vector<NodeDraw> draws;
  std::uint32_t partialNodes = 0;  // front nodes drawn with fewer triangles than their own
  std::uint32_t splatNodes = 0;    // front nodes drawn as splats
  std::uint64_t splats = 0;        // splats drawn
  QuadtreeWalk quadtree;  // the cells the culling walk tested and skipped (QuadtreeCulling)
  // View-dependent rendering (VdrSelector; the front is then clusters): this frame's vertex
  // splits (forced ones included) and edge collapses, the clusters on the active cluster lists,
  // and the error bound the frame was refined to (pixels).
  std::uint32_t vertexSplits = 0;
  std::uint32_t edgeCollapses = 0;
  std::uint32_t activeClusters = 0;
  double errorBoundPx = 0.0;
};

// The paper's constants (Lakhia III-C) plus the few this implementation adds; all documented.
struct LakhiaParams {
  double c_targetTime = 30.0;  // ms per frame: the budget (the paper's Fig. 9 uses 30 ms)
  double c_vis = 4.0;          // vis = 1 + c_vis * frustumVis: weight of being in the frustum
  // frustumVis falls linearly from 1 (touching the frustum) to 0 at c_visFalloff node-box
  // diagonals outside it (scale-free: a small node must be nearer the frustum to matter).
  double c_visFalloff = 1.0;
  // foreshorten = 1 + facing * c_fore, facing = -(view . avgNormal): +1 for a surface facing the
  // camera (its normal points back along the view direction), -1 facing away. Keep c_fore in
  // [0,1) so foreshorten stays positive; it is clamped at 0 anyway.
  double c_fore = 0.5;
  // The distance is measured from the camera moved by c_velocity seconds of its velocity
  // (the paper's "portion of the user's velocity": nodes ahead gain priority).
  double c_velocity = 0.5;
  double c_minDistance = 1.0;  // world units: distance = max(this, distance to box); no 1/0
  double c_minCost = 1.0;      // cost floor (one triangle): priority and timeNeeded stay finite
  // hyst is clamped to [-c_hystLimit, c_hystLimit]. Not a multiple of c_hystSwitch: a saturated
  // counter that dips slightly below the limit (noise) then keeps its trunc(hyst/c_hystSwitch).
  double c_hystLimit = 5.0;
  double c_hystSwitch = 2.0;   // cumHyst = sum trunc(hyst / c_hystSwitch); in [1, c_hystLimit]
  double c_hystInitial = 0.0;  // hyst of a node not visited the frame before (paper: 0)
  // Refinement threshold (an addition to the paper, in units of cumHyst). The paper draws the
  // children whenever cumHyst >= 0 and the parent when cumHyst < 0: a single threshold. With a
  // noisy frame time, v_time jitters by a few %, the urgency of a group whose children just fit
  // jitters around 0, its hyst random-walks across -c_hystSwitch and the group toggles forever
  // under a still camera. So a group whose parent was drawn last frame is refined only when
  // cumHyst >= c_hystRefine; a group already refined stays refined while cumHyst >= 0 (the
  // paper's rule). 0 gives the paper's behaviour; 1 needs hyst >= c_hystSwitch for a lone child,
  // always reachable because c_hystSwitch <= c_hystLimit.
  long long c_hystRefine = 1;
  // v_time feedback (see VTimeFeedback).
  double vTimeInitial = 1e-5;  // ms per unit of cost: 100 M triangles/s as a first guess
  double feedbackGain = 0.2;
  double feedbackMaxRatio = 4.0;
  // A real change, not noise (an addition): when the median of the last three frames is more
  // than feedbackJumpRatio times off, v_time jumps to it (within feedbackMaxRatio^2 a frame)
  // instead of moving by r^gain. Frame-time noise moves the median by ~10%; a new view, effect
  // or machine load moves it by 2-10x, and a 10x change is then followed within 3 frames
  // instead of ~10. 0 disables it.
  double feedbackJumpRatio = 2.0;
  // Slices are capped at c_demandMargin times the need of the node's leaves (see sliceSiblings).
  double c_demandMargin = 1.5;
  // The selector aims at c_aim * c_targetTime (an addition): the slices share that, and the
  // budget fill's band is relative to it. Below 1 the median frame sits further under the
  // target and fewer frames go over it: a trade-off whose measured difference (walk_bench,
  // docs/results.md) is about as large as the run-to-run spread on a 2-core machine, so the
  // default aims at the target itself.
  double c_aim = 1.0;
  // Budget fill after the walk (see LakhiaSelector::fillBudget): hysteresis band on the frame
  // total. New refinements are made only below (1 - c_fillAdd) of the aim, judged by the larger
  // of v_time and a steadier v_time fed at c_fillGain (VTimeFeedback), so that a dip of v_time
  // (10% frame-time noise moves it by ~3%) does not add refinements. Refinements kept from last
  // frame stay while the steadier v_time puts the total within (1 + c_fillKeep) of the aim and
  // the fast one within (1 + c_fillFast): noise does not remove them, a real change does. With
  // 10% white frame-time noise a still camera flickers when the band on one v_time is narrower
  // than ~15% ([0.97, 1.1] does, [0.95, 1.1] does not); on the steadier one [0.95, 1.05] holds
  // (StillCameraSettlesAndNeverFlickers), and keeps the frames nearer the target.
  double c_fillKeep = 0.05;
  double c_fillAdd = 0.05;
  double c_fillFast = 0.1;
  double c_fillGain = 0.05;
  // Shedding (an addition): the urgency hysteresis keeps a refined group while its counters
  // are positive, which after a sudden slowdown (a 10x dearer view, a loaded machine) keeps the
  // frame several times over budget for ~8 frames. When the front's estimate by the fast
  // v_time exceeds (1 + c_shed) of the aim, the refined groups of lowest priority are collapsed
  // back into their parents until it fits the aim. Far outside the fill's band, so noise
  // never triggers it.
  double c_shed = 0.25;
  // Benefit from geometric error (an addition; 1 on, 0 the paper's, -1 chosen by the store).
  // Where the store records geometric errors (hlodr's builder and 3D Tiles do), a node's benefit
  // is vis * foreshorten * the geometric error its drawing removes, projected in pixels at its
  // distance: its own error, or its parent's where it has none (a leaf). Eq. 2's static benefit
  // stands in for accuracy with the triangle count, and eq. 3 divides it by distance^2: on a
  // terrain whose errors vary 30-40x within a level that spent the budget near the camera on
  // flat tiles that a screen-space error leaves coarse (docs/results.md, "3D Tiles"). -1, the
  // default, turns it on for a store imported from a tileset that hlodr did not write (its
  // errors are what the tileset's author steers refinement by) and leaves the paper's benefit
  // on hlodr's own stores: their errors are geometric distances that do not see a baked
  // texture's blur, and at street level in a city with cell nodes the error benefit drew the
  // nearest facades coarse and a cell far off instead.
  double c_errorBenefit = -1.0;
};

struct SelectorParams {
  LakhiaParams lakhia;      // budget, v_time loop and the priority terms shared by all selectors
  double ssePixels = 16.0;  // SseSelector: refine while projected geometricError exceeds this
  // Frustum culling starts at the block quadtree (QuadtreeCulling): the same fronts, fewer roots
  // looked at. Off: every root is evaluated (for comparison; `--params quadtreeCulling=0`).
  bool quadtreeCulling = true;
  // Parry's hybrid rendering (sec. 3, 5): a node with splats whose box projects to fewer than
  // splatPixels pixels (its diagonal) is drawn as its splats, which cost c_splat units of cost
  // (eq. 1) each. Off by default (`--splats on`, `--params splats=1`).
  bool splats = false;
  double splatPixels = 4.0;
  double c_splat = 0.5;
  // Occlusion culling: an occluded node's load priority is scaled by c_occludedLoad (it is
  // not drawn, so a visible node's load comes first), and the children of one refined within
  // the last c_occludedKeepFrames frames stay wanted at that priority, so that they are still
  // resident when it comes back into view.
  double c_occludedLoad = 0.1;
  double c_occludedKeepFrames = 60.0;
  // Lakhia: a front node with a progression (a parry store) whose time slice buys less than its
  // timeNeeded is drawn with the triangles the slice buys, down to its coarsest (Parry's arrays
  // drawn at any count), instead of whole. `--params progressive=0` draws whole nodes only.
  bool progressive = true;
};

// Sets one constant by its name in the code (c_aim, c_fillAdd, feedbackGain, ssePixels, ...;
// c_targetTime is the budget, set apart). An Error names the known ones.
Status setSelectorParam(SelectorParams& params, std::string_view name, double value);
// A comma-separated list of NAME=VALUE, as `hlodr render --params` takes it; all or nothing.
Status setSelectorParams(SelectorParams& params, std::string_view list);
std::string selectorParamNames();  // space-separated

// The v_time feedback loop (Lakhia III-C: "v_time is adjusted in a feedback loop based on
// comparing actual time used to render a frame with the estimated render time").
// Update in the log domain: v_time <- v_time * r^gain, r = k / v_time, r clamped to
// [1/maxRatio, maxRatio], where k is the median of the last three observations
// measuredMs / drawnCost. Without a fixed overhead each observation is the true ms-per-cost
// times noise, so log(v_time/k) shrinks by (1-gain) per frame: a first-order low-pass with no
// overshoot for 0 < gain <= 1 (no oscillation). The median of three (an addition) passes a
// change that lasts two frames and drops a lone outlier frame (a page fault, a scheduler
// hiccup) entirely; the clamp bounds what the first frames can do (maxRatio^gain). A median
// more than jumpRatio off is a real change: v_time jumps to it (clamped to maxRatio^2), so that
// a 10x change is followed within three frames (LakhiaParams::feedbackJumpRatio).
class VTimeFeedback {
 public:
  VTimeFeedback(double initial, double gain, double maxRatio, double jumpRatio = 0.0);
  // drawnCost: the summed cost of the frame that took measuredMs. Ignored when either is not
  // positive and finite (an empty frame says nothing about the cost per triangle).
  void update(double measuredMs, double drawnCost);
  double vTime() const { return vTime_; }
  void set(double vTime);  // also forgets the observations

 private:
  double vTime_;
  std::array<double, 3> observed_{};  // the last observations of measuredMs / drawnCost
  std::size_t observedCount_ = 0;
  double gain_;
  double maxRatio_;
  double jumpRatio_;
};

class Selector {
 public:
  Selector(const Skeleton& skeleton, const SelectorParams& params);
  virtual ~Selector() = default;
  Selector(const Selector&) = delete;
  Selector& operator=(const Selector&) = delete;

  virtual std::string_view name() const = 0;
  virtual Selection select(const View& view, const Residency& residency) = 0;
  // Whether the front depends on the budget and v_time (not so for a fixed error or `full`).
  virtual bool budgeted() const { return false; }
  // Whether makeSelector(name()) makes a fresh one like it (FrameDriver::start's probe draws its
  // front with one); not so for a selector whose state is a runtime of its own.
  virtual bool remakeable() const { return true; }

  // The measured time of the geometry pass of the frame drawn from the last selection (ms):
  // without the View::spentMs it was selected with and without the other passes that draw the
  // front (View::frontDraws). v_time is the geometry pass's ms per unit of cost.
  void feedback(double measuredMs);

  double vTime() const { return feedback_.vTime(); }
  // The same feedback at c_fillGain: a steadier v_time for decisions that must not follow
  // frame-time noise (LakhiaSelector's budget fill adds refinements only when both agree).
  double vTimeSteady() const { return steadyFeedback_.vTime(); }
  void setVTime(double v) {
    feedback_.set(v);
    steadyFeedback_.set(v);
  }
  double targetMs() const { return params_.lakhia.c_targetTime; }
  void setTargetMs(double ms) { params_.lakhia.c_targetTime = ms; }
  const SelectorParams& params() const { return params_; }
  const Skeleton& skeleton() const { return skeleton_; }
  // The estimated cost of the last selection's front (what feedback() divides by).
  double lastEstimatedCost() const { return lastEstimatedCost_; }

 protected:
  // Bookkeeping shared by all selectors: frame counter, toggles, the front and its counters.
  Selection beginFrame(const View& view);
  // After the front is chosen: what to draw of each node (Selection::draws). Splats for the
  // nodes that project to fewer than splatPixels (when on); whole nodes otherwise, or
  // trianglesFor(node) where it gives fewer (Lakhia's slices); then the front's cost and
  // triangles are recounted from the draws and finishFrame runs.
  template <class TrianglesFor>
  void planDraws(const View& view, Selection& s, TrianglesFor&& trianglesFor);
  void planDraws(const View& view, Selection& s) {
    planDraws(view, s, [&](std::uint32_t n) { return skeleton_.nodes[n].numTri; });
  }
  // The cost (eq. 1) of drawing d of node n: whole, a share of its triangles, or its splats.
  double drawCost(std::uint32_t node, const NodeDraw& d) const;
  void markRefined(std::uint32_t node, Selection& s);
  void markDrawn(std::uint32_t node, Selection& s);
  void finishFrame(Selection& s);
  // After a walk: replaces a drawn node in s by its (resident, visible) children, as if the walk
  // had refined it (toggle counters included). Call finishFrame again afterwards.
  void replaceByChildren(std::uint32_t node, const std::vector<std::uint32_t>& children,
                         Selection& s);
  // The inverse: a node refined this frame whose children are all drawn (none refined further)
  // is drawn instead of them. Call finishFrame again afterwards.
  void replaceByParent(std::uint32_t node, Selection& s);
  // The block roots to look at this frame, in Skeleton::roots order: those of the quadtree
  // cells within c_visFalloff of the frustum (QuadtreeCulling; every root with quadtreeCulling
  // off). Every root left out is invisible with frustumVis 0. Records the walk in s.quadtree.
  const std::vector<std::uint32_t>& candidateRoots(const View& view, Selection& s);
  // The node's box lies wholly beyond View::fogCullDistance of this frame.
  bool fullyFogged(std::uint32_t node) const;
  // A node in the frustum that the last frame's occlusion queries found hidden (View::occlusion):
  // recorded once a frame in s.occluded, and left out of the front with its subtree.
  bool occludedNow(std::uint32_t node, Selection& s);
  bool refinedThisFrame(std::uint32_t node) const { return refinedFrame_[node] == frame_; }
  double effectiveCost(std::uint32_t node) const;  // max(cost, c_minCost)
  bool refinedLastFrame(std::uint32_t node) const { return refinedFrame_[node] == frame_ - 1; }

  // The breadth-first front walk every selector shares (Lakhia III-C: siblings are decided
  // before their children). queue starts with the visible roots. For each node: a leaf, or one
  // that wantsChildren(n) declines, is drawn; otherwise visit(c) is called for each child (it
  // records the child for the loader and returns its visibility), refine(n, visibleChildren)
  // decides whether they replace n, and if one of them is not resident n is drawn instead.
  template <class WantsChildren, class Visit, class Refine>
  void walkFront(std::vector<std::uint32_t> queue, const Residency& residency, Selection& s,
                 WantsChildren&& wantsChildren, Visit&& visit, Refine&& refine) {
    const auto& nodes = skeleton_.nodes;
    std::vector<std::uint32_t> children;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const std::uint32_t n = queue[head];
      // Fully fogged: drawn it would be the fog colour, which the background already is.
      if (fullyFogged(n)) {
        ++s.fogCulled;
        continue;
      }
      const NodeInfo& info = nodes[n];
      // A decoded skeleton keeps every child range inside the nodes (decodeSkeleton).
      assert(info.childCount == 0 ||
             (info.firstChild < nodes.size() && info.childCount <= nodes.size() - info.firstChild));
      const bool hasChildren = info.childCount > 0;
      if (!hasChildren || !wantsChildren(n)) {
        markDrawn(n, s);
        continue;
      }
      children.clear();
      bool hiddenChild = false;
      for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c)
        if (visit(c)) {
          if (fullyFogged(c))
            ++s.fogCulled;
          else if (occludedNow(c, s))
            hiddenChild = true;
          else
            children.push_back(c);
        }
      // Every child in view is hidden: so is the node's own surface, which approximates theirs.
      if (children.empty() && hiddenChild) continue;
      if (!refine(n, children)) {
        markDrawn(n, s);
        continue;
      }
      // A visible child that is not resident keeps all its siblings out: draw the parent.
      if (!std::all_of(children.begin(), children.end(),
                       [&](std::uint32_t c) { return residency.isResident(c); })) {
        ++s.coarserBecauseNotResident;
        for (std::uint32_t c : children)
          if (!residency.isResident(c)) s.notResident.push_back(c);
        markDrawn(n, s);
        continue;
      }
      // Refined: the visible children take the node's place (invisible ones are not drawn).
      markRefined(n, s);
      queue.insert(queue.end(), children.begin(), children.end());
    }
    finishFrame(s);
  }

  const Skeleton& skeleton_;
  SelectorParams params_;
  std::uint32_t frame_ = 0;

 private:
  static constexpr std::uint32_t kNever = 0xffffffffu;
  VTimeFeedback feedback_;
  VTimeFeedback steadyFeedback_;
  QuadtreeCulling culling_;
  std::vector<std::uint32_t> candidates_;
  glm::dvec3 fogEye_{0.0};
  double fogCullDistance_ = std::numeric_limits<double>::infinity();
  double lastEstimatedCost_ = 0.0;
  std::uint32_t maxLevel_ = 0;
  std::vector<std::uint32_t> drawnFrame_;       // last frame each node was drawn
  std::vector<std::uint32_t> drawnBefore_;      // drawnFrame_ before markDrawn set it this frame
  std::vector<std::uint32_t> refinedFrame_;     // last frame each node was replaced by children
  std::vector<std::uint32_t> refinedBefore_;    // refinedFrame_ before markRefined set it
  const OcclusionOracle* occlusion_ = nullptr;  // this frame's View::occlusion
  std::vector<std::uint32_t> occludedFrame_;    // last frame each node was found occluded
  void applyOcclusionToLoads(Selection& s) const;
};

template <class TrianglesFor>
void Selector::planDraws(const View& view, Selection& s, TrianglesFor&& trianglesFor) {
  s.draws.assign(s.front.size(), NodeDraw{});
  s.estimatedCost = 0.0;
  s.triangles = 0;
  s.partialNodes = s.splatNodes = 0;
  s.splats = 0;
  for (std::size_t i = 0; i < s.front.size(); ++i) {
    const std::uint32_t n = s.front[i];
    const NodeInfo& info = skeleton_.nodes[n];
    NodeDraw& d = s.draws[i];
    if (params_.splats && info.splatCount > 0 &&
        projectedPixels(view, info.bounds) < params_.splatPixels) {
      d.splats = true;
      ++s.splatNodes;
      s.splats += info.splatCount;
    } else {
      d.triangles = info.progressive()
                        ? std::clamp<std::uint32_t>(trianglesFor(n), info.minTri, info.numTri)
                        : info.numTri;
      if (d.triangles < info.numTri) ++s.partialNodes;
      s.triangles += d.triangles;
    }
    s.estimatedCost += drawCost(n, d);
  }
  applyOcclusionToLoads(s);
  finishFrame(s);
}

// "lakhia", "sse", "fs" or "full"; an unknown name is an Error listing the known ones. "vdr"
// is an Error too: VdrSelector needs a store's objects (service::Session makes it).
Result<std::unique_ptr<Selector>> makeSelector(std::string_view name, const Skeleton& skeleton,
                                               const SelectorParams& params = {});

}  // namespace hlod
