#pragma once
// The error bound of each frame, chosen so that the front fits the frame's time budget. Manocha
// refines to a fixed "pixels of error"; Hoppe 1997 (sec. 4.4, "regulation") adjusts its
// threshold every frame so that the number of active faces stays near a target. Here the target
// is a cost (Lakhia's eq. 1) derived from the time budget through the v_time feedback loop that
// drives the Lakhia selector: targetCost = drawBudgetMs / v_time.
// Model: the front's cost falls as a power of the bound, cost ~ bound^-exponent (2 for a
// surface seen in perspective: triangles per square pixel of error), so the bound that meets
// targetCost from (bound, cost) is bound * (cost / targetCost)^(1 / exponent). A step moves the
// bound at most maxStep times either way and keeps it within [minPx, maxPx]; within tolerance
// of the target the bound stays (frame-time noise moves targetCost by a few %: no churn).
#include <algorithm>
#include <cmath>

namespace hlod::vdr {

struct BoundControlParams {
  double initialPx = 4.0;
  double minPx = 0.25;
  double maxPx = 1024.0;
  double exponent = 2.0;
  double maxStep = 4.0;
  double tolerance = 0.05;
};

class ErrorBoundControl {
 public:
  explicit ErrorBoundControl(const BoundControlParams& p = {})
      : p_(p), bound_(std::clamp(p.initialPx, p.minPx, p.maxPx)) {}

  double bound() const { return bound_; }
  void set(double px) {
    if (std::isfinite(px) && px > 0.0) bound_ = std::clamp(px, p_.minPx, p_.maxPx);
  }
  // Whether `cost` at the present bound is within tolerance of targetCost.
  bool meets(double cost, double targetCost) const {
    return targetCost > 0.0 && std::abs(cost / targetCost - 1.0) <= p_.tolerance;
  }
  // The bound for targetCost, from the cost the front had at the present bound; stored and
  // returned. Unchanged within tolerance, for a cost of 0 with a target above it (nothing to
  // draw: the bound cannot help), and for targets that are not positive and finite.
  double step(double cost, double targetCost) {
    if (!(targetCost > 0.0) || !std::isfinite(targetCost) || !std::isfinite(cost)) return bound_;
    if (meets(cost, targetCost)) return bound_;
    if (!(cost > 0.0)) return bound_;
    const double ratio =
        std::clamp(std::pow(cost / targetCost, 1.0 / p_.exponent), 1.0 / p_.maxStep, p_.maxStep);
    bound_ = std::clamp(bound_ * ratio, p_.minPx, p_.maxPx);
    return bound_;
  }
  const BoundControlParams& params() const { return p_; }

 private:
  BoundControlParams p_;
  double bound_;
};

}  // namespace hlod::vdr
