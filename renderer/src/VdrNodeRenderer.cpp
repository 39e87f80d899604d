#include "renderer/VdrNodeRenderer.h"

#include <algorithm>
#include <chrono>

namespace renderer {

hlod::Result<std::unique_ptr<VdrNodeRenderer>> VdrNodeRenderer::create(
    GlContext& context, hlod::vdr::VdrRuntime& runtime, const RenderOptions& options,
    double minActiveRatio, std::uint64_t gpuBudgetBytes) {
  auto inner = GpuNodeRenderer::create(context, runtime.skeleton(), options);
  if (!inner) return inner.error();
  return std::unique_ptr<VdrNodeRenderer>(
      new VdrNodeRenderer(runtime, std::move(*inner), minActiveRatio, gpuBudgetBytes));
}

VdrNodeRenderer::VdrNodeRenderer(hlod::vdr::VdrRuntime& runtime,
                                 std::unique_ptr<GpuNodeRenderer> inner, double minActiveRatio,
                                 std::uint64_t budget)
    : runtime_(runtime),
      inner_(std::move(inner)),
      minActiveRatio_(minActiveRatio),
      budget_(budget),
      uploaded_(runtime.skeleton().nodes.size(), kNoCopy),
      lastDrawn_(runtime.skeleton().nodes.size(), 0) {}

hlod::Result<hlod::DrawReport> VdrNodeRenderer::draw(const hlod::Camera& camera,
                                                     std::span<const std::uint32_t> front,
                                                     std::span<const hlod::NodeDraw> draws,
                                                     const hlod::OcclusionPlan* /*occlusion*/) {
  // Clusters are not occlusion units yet: sessions draw vdr with occlusion culling off.
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  ++frame_;
  counters_ = {};
  // The front's clusters whose faces changed since their copy: rebuilt and uploaded now.
  for (std::uint32_t c : front) {
    if (c >= uploaded_.size()) continue;
    lastDrawn_[c] = frame_;
    const std::uint64_t version = runtime_.version(c);
    if (uploaded_[c] == version) continue;
    hlod::vdr::ArrayForm form{};
    auto mesh =
        std::make_shared<const hlod::LocalMesh>(runtime_.clusterArrays(c, minActiveRatio_, &form));
    // The residency keeps a node's first copy: the old one goes first.
    if (uploaded_[c] == kNoCopy)
      held_.push_back(c);
    else
      inner_->evict(c);
    inner_->queueUpload(c, std::move(mesh));
    uploaded_[c] = version;
    ++counters_.rebuilt;
    counters_.vertexArrays += form == hlod::vdr::ArrayForm::VertexArray;
  }
  if (counters_.rebuilt > 0)
    if (auto u = inner_->upload(1e300, 0); !u) return u.error();
  const double prepareMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  // Each cluster whole: its triangles are what the copy holds.
  std::vector<hlod::NodeDraw> whole(front.size());
  for (std::size_t i = 0; i < front.size(); ++i)
    whole[i].triangles = i < draws.size() ? draws[i].triangles : 0;
  auto report = inner_->draw(camera, front, whole);
  if (!report) return report.error();
  const auto after = Clock::now();
  keepWithinBudget();
  const double refineMs = runtime_.takeRefineMs() + prepareMs +
                          std::chrono::duration<double, std::milli>(Clock::now() - after).count();
  report->ms += refineMs;
  report->passes.push_back({"refine", refineMs});
  return report;
}

void VdrNodeRenderer::keepWithinBudget() {
  if (budget_ == 0 || inner_->residency().gpuBytes() <= budget_) return;
  // Least recently drawn first; this frame's clusters last (they leave only when the front
  // alone is over the budget).
  std::sort(held_.begin(), held_.end(), [&](std::uint32_t a, std::uint32_t b) {
    return lastDrawn_[a] != lastDrawn_[b] ? lastDrawn_[a] < lastDrawn_[b] : a < b;
  });
  std::size_t freed = 0;
  while (freed < held_.size() && inner_->residency().gpuBytes() > budget_) {
    const std::uint32_t c = held_[freed++];
    inner_->evict(c);
    uploaded_[c] = kNoCopy;
    ++counters_.evicted;
  }
  held_.erase(held_.begin(), held_.begin() + std::ptrdiff_t(freed));
}

}  // namespace renderer
