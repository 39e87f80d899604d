#pragma once
// Funkhouser & Sequin style greedy selection under a time budget: start from the visible hlod_0
// nodes, then repeatedly apply the refinement (a node replaced by its visible children) with the
// largest added benefit per added cost, while the estimated frame time (v_time * cost, the same
// estimate as Lakhia's) stays within c_targetTime. Benefit is Lakhia's benefit; no hysteresis.
#include <vector>

#include "hlod/runtime/Selector.h"

namespace hlod {

class FsSelector final : public Selector {
 public:
  FsSelector(const Skeleton& skeleton, const SelectorParams& params = {});
  std::string_view name() const override { return "fs"; }
  bool budgeted() const override { return true; }
  Selection select(const View& view, const Residency& residency) override;

 private:
  // Per-node scratch, kept between frames so a frame costs O(visited), not O(nodes).
  std::vector<double> benefit_;
  std::vector<std::uint8_t> visible_;
  std::vector<std::uint8_t> drawn_;
};

}  // namespace hlod
