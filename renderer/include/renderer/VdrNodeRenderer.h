#pragma once
// hlod::NodeRenderer for view-dependent rendering (`--selector vdr`): draws a VdrRuntime's
// clusters as the nodes of its cluster skeleton, through a GpuNodeRenderer made on that skeleton,
// so that every pass and effect (and a cluster's box, for queries) applies to clusters as to
// nodes. The runtime holds every object in memory: the loader's events (nodes of the store) are
// ignored, and every cluster counts as on the GPU (its arrays are made when it is drawn).
//
// Manocha sec. 5.1.3: before the drawing, each cluster of the front whose faces changed since
// its GPU copy was made is rebuilt (VdrRuntime::clusterArrays: its vertex array, or a compacted
// one under minActiveRatio) and uploaded. Copies stay in GPU memory over frames under the GPU
// memory budget, the least recently drawn replaced first; "when the front size exceeds the
// memory requirement, we still use GPU memory, but do not attempt to keep clusters in this
// memory for more than one frame": what the budget cannot hold after a frame is freed then.
// The refinement's CPU time (VdrRuntime::takeRefineMs) and the rebuilding and uploads are
// added to the frame's time as the pass "refine".
#include <cstdint>
#include <memory>
#include <vector>

#include "hlod/vdr/VdrRuntime.h"
#include "renderer/GpuNodeRenderer.h"

namespace renderer {

struct VdrDrawCounters {
  std::uint32_t rebuilt = 0;       // clusters rebuilt and uploaded by the last draw
  std::uint32_t vertexArrays = 0;  // of them, as vertex arrays (the others compacted)
  std::uint32_t evicted = 0;       // copies freed for the budget after the last draw
};

class VdrNodeRenderer final : public hlod::NodeRenderer {
 public:
  // On `context`, current now and at every later call; the runtime must outlive the renderer.
  // gpuBudgetBytes 0: no budget.
  static hlod::Result<std::unique_ptr<VdrNodeRenderer>> create(GlContext& context,
                                                               hlod::vdr::VdrRuntime& runtime,
                                                               const RenderOptions& options,
                                                               double minActiveRatio = 0.25,
                                                               std::uint64_t gpuBudgetBytes = 0);

  void queueUpload(std::uint32_t, std::shared_ptr<const hlod::LocalMesh>) override {}
  void evict(std::uint32_t) override {}
  hlod::Result<hlod::UploadReport> upload(double, std::uint64_t) override {
    return hlod::UploadReport{};
  }
  std::size_t pendingUploads() const override { return 0; }
  const hlod::Residency& onGpu() const override { return all_; }
  hlod::Result<hlod::DrawReport> draw(const hlod::Camera& camera,
                                      std::span<const std::uint32_t> front,
                                      std::span<const hlod::NodeDraw> draws,
                                      const hlod::OcclusionPlan* occlusion = nullptr) override;
  hlod::Image readback() override { return inner_->readback(); }
  bool drawsShadowPass() const override { return inner_->drawsShadowPass(); }
  hlod::metrics::Mask coverage() { return inner_->coverage(); }

  void setGpuBudget(std::uint64_t bytes) override { budget_ = bytes; }
  const VdrDrawCounters& counters() const { return counters_; }
  GpuNodeRenderer& inner() { return *inner_; }
  const GpuNodeRenderer& inner() const { return *inner_; }

 private:
  VdrNodeRenderer(hlod::vdr::VdrRuntime& runtime, std::unique_ptr<GpuNodeRenderer> inner,
                  double minActiveRatio, std::uint64_t budget);
  void keepWithinBudget();

  hlod::vdr::VdrRuntime& runtime_;
  std::unique_ptr<GpuNodeRenderer> inner_;
  double minActiveRatio_;
  std::uint64_t budget_;
  hlod::AllResident all_;
  static constexpr std::uint64_t kNoCopy = ~0ull;
  std::vector<std::uint64_t> uploaded_;   // per cluster: the version its GPU copy holds
  std::vector<std::uint64_t> lastDrawn_;  // per cluster: the frame it was last drawn
  std::vector<std::uint32_t> held_;       // clusters with a GPU copy
  std::uint64_t frame_ = 0;
  VdrDrawCounters counters_;
};

}  // namespace renderer
