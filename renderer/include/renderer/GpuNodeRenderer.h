#pragma once
// hlod::NodeRenderer on a GL context: a session's GpuResidency and its Renderer (framebuffer of
// the session's size, shader variants of its effects). Draws camera-relative with near and far
// planes fitted to the model's bounds. Every call needs the context current on this thread.
#include <algorithm>
#include <memory>

#include "hlod/runtime/FrameDriver.h"
#include "renderer/GpuResidency.h"
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
                                      std::span<const hlod::NodeDraw> draws) override;
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
  hlod::Aabb bounds_;  // of the whole model: the clip planes
};

// Near and far planes that hold the box seen from the camera (reversed-Z makes a wide range
// safe).
void clipPlanesFor(const glm::dvec3& eye, const hlod::Aabb& bounds, double& zNear, double& zFar);

}  // namespace renderer
