#pragma once
// View-dependent rendering under the frame budget, as a selector ("vdr"): Manocha sec. 5.1 on a
// VdrRuntime, with the error bound chosen every frame for the budget instead of fixed.
//
// A frame: the target cost is the draw budget over v_time (the Lakhia selector's feedback loop:
// Selector::feedback learns v_time from the measured frames, here in ms per unit of eq. 1's cost
// of the clusters drawn); every object's active clusters are refined to the present bound; the
// front is the active clusters in the view frustum, each drawn whole (all its live faces); when
// the front's cost misses the target by more than the tolerance, the bound is moved for it
// (ErrorBoundControl) and the clusters refined again, at most `corrections` times. The front's
// nodes are those of the runtime's cluster skeleton (VdrRuntime::skeleton), which is this
// selector's skeleton. The refinement's CPU time is recorded in the runtime, and the renderer
// (renderer::VdrNodeRenderer) counts it in the frame.
//
// It cannot be made again by name (it holds the objects' refinement state): FrameDriver::start
// measures its v_time with frames of its own at the default view instead of a fresh selector's.
#include "hlod/runtime/Selector.h"
#include "hlod/vdr/ErrorBoundControl.h"
#include "hlod/vdr/VdrRuntime.h"

namespace hlod {

struct VdrSelectorParams {
  vdr::BoundControlParams bound;
  int corrections = 2;
};

class VdrSelector final : public Selector {
 public:
  // The runtime must outlive the selector.
  VdrSelector(vdr::VdrRuntime& runtime, const SelectorParams& params,
              const VdrSelectorParams& vdr = {});
  std::string_view name() const override { return "vdr"; }
  Selection select(const View& view, const Residency& residency) override;
  bool budgeted() const override { return true; }
  bool remakeable() const override { return false; }

  double boundPx() const { return control_.bound(); }

 private:
  vdr::VdrRuntime& runtime_;
  VdrSelectorParams vdr_;
  vdr::ErrorBoundControl control_;
};

}  // namespace hlod
