#pragma once
// Lakhia, "Efficient Interactive Rendering of Detailed Models with Hierarchical Levels of Detail"
// (shared/seeds/lakhia-hlod.txt), sec. III-C: breadth-first top-down front selection with
// cost/benefit priority, time slicing (eq. 4), v_time feedback and urgency hysteresis.
#include <cstdint>
#include <vector>

#include "hlod/runtime/Camera.h"
#include "hlod/runtime/Selector.h"

namespace hlod {

// The priority heuristics of III-C for one node under one view.
struct NodePriority {
  double frustumVis = 0.0;   // 1 touching the frustum, falling linearly to 0 outside
  double vis = 1.0;          // 1 + c_vis * frustumVis
  double foreshorten = 1.0;  // 1 + facing * c_fore, at least 0
  double distance = 1.0;     // max(c_minDistance, distance from the look-ahead camera to the box)
  // staticBenefit * vis * foreshorten / distance^2; or, given the error the node removes,
  // that error in pixels at the distance * vis * foreshorten (LakhiaParams::c_errorBenefit)
  double benefit = 0.0;
  double priority = 0.0;  // benefit / max(cost, c_minCost)
  bool visible = false;   // the box touches the view frustum
};

// Per-frame quantities shared by every node's priority (frustum, look-ahead position).
class PriorityModel {
 public:
  PriorityModel(const View& view, const LakhiaParams& params);
  // errorRemoved > 0: the geometric error drawing the node removes, its benefit's measure.
  NodePriority evaluate(const NodeInfo& node, double errorRemoved = 0.0) const;
  const Frustum& frustum() const { return frustum_; }

 private:
  const LakhiaParams& params_;
  Frustum frustum_;
  glm::dvec3 lookAhead_;     // camera position + c_velocity * velocity
  glm::dvec3 view_;          // the image plane normal: the camera's forward direction
  double pixelsPerUnitAt1_;  // pixels one world unit covers face-on at distance 1
};

class LakhiaSelector final : public Selector {
 public:
  LakhiaSelector(const Skeleton& skeleton, const SelectorParams& params = {});

  std::string_view name() const override { return "lakhia"; }
  bool budgeted() const override { return true; }
  Selection select(const View& view, const Residency& residency) override;

  // Inspection for tests and debugging: the values of the last select().
  double hyst(std::uint32_t node) const { return hyst_[node]; }
  double timeSlice(std::uint32_t node) const { return timeSlice_[node]; }
  double timeNeeded(std::uint32_t node) const;
  double priority(std::uint32_t node) const { return priority_[node]; }
  bool visitedLastFrame(std::uint32_t node) const { return visitFrame_[node] == frame_; }

 private:
  // Time slices (eq. 4) and hysteresis for one sibling set; returns cumHyst.
  long long sliceSiblings(const std::vector<std::uint32_t>& visibleSiblings, double shareTime);
  void updateHyst(std::uint32_t node);
  // Spends what the slices left of c_targetTime on further refinements (see the .cpp).
  template <class Visit>
  void fillBudget(Selection& s, const Residency& residency, Visit&& visit);
  // Coarsens a front that the hysteresis keeps far over the aim (see the .cpp).
  void shedBudget(Selection& s);
  // The triangles node n's time slice buys, when it was sliced this frame and has a progression
  // (in steps of its range); its numTri otherwise.
  std::uint32_t trianglesBought(std::uint32_t n) const;
  static constexpr double kProgressiveSteps = 32.0;
  // A node with children and no geometric error, in a store whose inner nodes carry errors (a
  // 3D Tiles tile with geometricError 0): its children draw the same surface, so it is drawn
  // as a leaf, as SSE and 3D Tiles viewers do.
  bool exact(std::uint32_t n) const {
    return errorsKnown_ && !(skeleton_.nodes[n].geometricError > 0.0);
  }

  std::vector<double> hyst_;
  std::vector<double> timeSlice_;
  std::vector<double> priority_;
  std::vector<std::uint32_t> visitFrame_;      // frame a node's hyst was last updated
  std::vector<double> leafCost_;               // summed cost of each subtree's leaves
  std::vector<std::uint32_t> evaluatedFrame_;  // frame priority_ and visible_ were computed
  std::vector<std::uint8_t> visible_;          // in the frustum, as of evaluatedFrame_
  std::vector<std::uint8_t> capped_;           // sliceSiblings scratch
  std::vector<std::uint32_t> slicedFrame_;     // frame a node's timeSlice_ was last set
  double aimMs_ = 0.0;         // c_aim * the drawing's budget this frame: what the slices share
  bool errorsKnown_ = false;   // some node with children has a geometric error above 0
  bool errorBenefit_ = false;  // benefits from errors (LakhiaParams::c_errorBenefit)
  // The geometric error drawing node n removes where benefits come from errors, else 0.
  double errorRemoved(std::uint32_t n) const;
};

}  // namespace hlod
