#pragma once
// hlod::NodeRenderer on a GL context: a session's GpuResidency and its Renderer (framebuffer of
// the session's size, shader variants of its effects). Draws camera-relative with near and far
// planes fitted to the model's bounds. Every call needs the context current on this thread.
#include <algorithm>
#include <memory>

#include "hlod/runtime/FrameDriver.h"
#include "renderer/GpuResidency.h"
#include "renderer/IdBuffer.h"
#include "renderer/Renderer.h"

namespace renderer {

class GpuNodeRenderer final : public hlod::NodeRenderer {
 public:
  // The Renderer is created on `context`, which must be current now and at every later call.
  static hlod::Result<std::unique_ptr<GpuNodeRenderer>> create(GlContext& context,
                                                               const hlod::Skeleton& skeleton,
                                                               const RenderOptions& options);

  void queueUpload(std::uint32_t node, std::shared_ptr<const hlod::LocalMesh> mesh) override;
  void evict(std::uint32_t node) override;
  hlod::Result<hlod::UploadReport> upload(double budgetMs, std::uint64_t budgetBytes) override;
  std::size_t pendingUploads() const override { return residency_.pending(); }
  const hlod::Residency& onGpu() const override { return residency_.onGpu(); }
  hlod::Result<hlod::DrawReport> draw(const hlod::Camera& camera,
                                      std::span<const std::uint32_t> front,
                                      std::span<const hlod::NodeDraw> draws,
                                      const hlod::OcclusionPlan* occlusion = nullptr) override;
  std::vector<hlod::OcclusionResult> occlusionResults() override;
  std::uint64_t gpuBytes() const override { return residency_.gpuBytes(); }
  std::uint32_t takeGpuEvictions() override { return residency_.takeEvictions(); }
  void setGpuBudget(std::uint64_t bytes) override;
  bool pendingOrOnGpu(std::uint32_t node) const override { return residency_.pendingOrOnGpu(node); }
  bool canDrawInParts() const override { return renderer_->canDrawInParts(); }
  hlod::Status beginParts(const hlod::Camera& camera, std::span<const std::uint32_t> front,
                          std::span<const hlod::NodeDraw> draws,
                          const hlod::OcclusionPlan* occlusion) override;
  hlod::Status drawPart(std::span<const std::size_t> positions) override;
  hlod::Result<hlod::DrawReport> endParts() override;
  // Debug view (`--show-occlusion`): the boxes of the nodes the last plan queried as hidden are
  // tinted over the frame, as Manocha's Fig. 5 shows the occluded clusters.
  void setShowOcclusion(bool show) { showOcclusion_ = show; }
  // A measurement (IdBuffer): what of these nodes, drawn as `draws` says (empty: whole), shows
  // from the camera. Nodes not on the GPU are left out. Leaves the occlusion answers alone.
  hlod::Result<VisibleCount> countVisible(const hlod::Camera& camera,
                                          std::span<const std::uint32_t> nodes,
                                          std::span<const hlod::NodeDraw> draws = {});
  // The occlusion-switch's HC (Manocha sec. 4.2): each node's box queried against the depth of
  // the last draw, from that draw's camera. Per node: 1 where samples passed, or where the box
  // reaches the near plane and is not queried (it counts as visible); 0 hidden.
  std::vector<std::uint8_t> queryBoxesOnLastDraw(std::span<const std::uint32_t> nodes);
  hlod::Image readback() override { return renderer_->readback(); }
  bool drawsShadowPass() const override {
    const auto& p = renderer_->passes();
    return std::find(p.begin(), p.end(), Pass::Shadow) != p.end();
  }
  hlod::metrics::Mask coverage() { return renderer_->coverage(); }

  Renderer& renderer() { return *renderer_; }
  const GpuResidency& residency() const { return residency_; }

 private:
  GpuNodeRenderer(const hlod::Skeleton& skeleton, std::unique_ptr<Renderer> renderer);

  const hlod::Skeleton& skeleton_;  // node bounds: the shadow map's fit
  std::unique_ptr<Renderer> renderer_;
  GpuResidency residency_;
  std::unique_ptr<hlod::GpuMemoryManager> memory_;  // the GPU budget, when one is set
  hlod::Aabb bounds_;                               // of the whole model: the clip planes
  bool showOcclusion_ = false;
  // The nodes of the last draw's queries, to map their answers back: per mesh drawn, its node;
  // per box batch issued, its nodes; nodes whose box was not queried (camera or near plane).
  std::vector<std::uint32_t> meshNodes_;
  std::vector<std::vector<std::uint32_t>> batchNodes_;
  std::vector<std::uint32_t> unqueried_;
  std::vector<hlod::OcclusionResult> answers_;  // the last frame's, until taken
  void collectAnswers();
  // What one frame's drawing needs: the view, the meshes with their query flags and node ids,
  // and the occlusion queries' boxes (FrameSetup); kept over the parts of a frame drawn in parts.
  struct FrameSetup {
    FrameView view;
    std::vector<std::uint32_t> front;
    std::vector<hlod::NodeDraw> draws;
    std::vector<std::uint8_t> queryDraw;  // per front position
    std::vector<std::vector<hlod::Aabb>> boxBatches;
    std::vector<const GpuMesh*> hiddenCasters;
    std::vector<hlod::Aabb> tint;
    OcclusionDraw occlusionDraw;
    bool hasOcclusion = false;
  };
  // Builds the frame's setup: its view, and the occlusion queries' boxes (a box that reaches
  // the near plane is not queried).
  void setUp(const hlod::Camera& camera, std::span<const std::uint32_t> front,
             std::span<const hlod::NodeDraw> draws, const hlod::OcclusionPlan* occlusion);
  // The mesh to draw for the front's node at `position` (nullptr: not on the GPU); records it
  // for the occlusion answers, with its query flag in queryMesh.
  const GpuMesh* meshFor(std::size_t position, std::vector<std::uint8_t>& queryMesh);
  bool reachesNear(const hlod::Aabb& box) const;
  hlod::DrawReport report(const FrameTiming& t) const;
  FrameSetup setup_;
  std::unique_ptr<IdBuffer> idBuffer_;
  double zNear_ = 0.0;
  glm::dvec3 eye_{0.0}, forward_{0.0, 0.0, -1.0};
};

// Near and far planes that hold the box seen from the camera (reversed-Z makes a wide range
// safe).
void clipPlanesFor(const glm::dvec3& eye, const hlod::Aabb& bounds, double& zNear, double& zFar);

}  // namespace renderer
