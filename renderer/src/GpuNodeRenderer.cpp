#include "renderer/GpuNodeRenderer.h"

#include <algorithm>
#include <cmath>

namespace renderer {

void clipPlanesFor(const glm::dvec3& eye, const hlod::Aabb& bounds, double& zNear, double& zFar) {
  const double radius = std::max(glm::length(bounds.size()) * 0.5, 1e-6);
  const double d = glm::length(eye - bounds.centre());
  zFar = d + radius * 1.5;
  zNear = std::max((d - radius) * 0.5, zFar * 1e-6);
}

hlod::Result<std::unique_ptr<GpuNodeRenderer>> GpuNodeRenderer::create(
    GlContext& context, const hlod::Skeleton& skeleton, const RenderOptions& options) {
  auto r = Renderer::create(context, options);
  if (!r) return r.error();
  return std::unique_ptr<GpuNodeRenderer>(new GpuNodeRenderer(skeleton, std::move(*r)));
}

GpuNodeRenderer::GpuNodeRenderer(const hlod::Skeleton& skeleton, std::unique_ptr<Renderer> renderer)
    : skeleton_(skeleton),
      renderer_(std::move(renderer)),
      residency_(renderer_->gl(), skeleton.nodes.size()) {
  for (std::uint32_t r : skeleton.roots) bounds_.extend(skeleton.nodes[r].bounds);
}

void GpuNodeRenderer::queueUpload(std::uint32_t node, std::shared_ptr<const hlod::LocalMesh> mesh) {
  residency_.queue(node, std::move(mesh));
}

void GpuNodeRenderer::evict(std::uint32_t node) {
  residency_.evict(node);
}

hlod::Result<hlod::UploadReport> GpuNodeRenderer::upload(double budgetMs,
                                                         std::uint64_t budgetBytes) {
  return residency_.upload(budgetMs, budgetBytes);
}

hlod::Result<hlod::DrawReport> GpuNodeRenderer::draw(const hlod::Camera& camera,
                                                     std::span<const std::uint32_t> front,
                                                     std::span<const hlod::NodeDraw> draws) {
  double zNear = camera.nearPlane, zFar = camera.farPlane;
  if (!bounds_.empty()) clipPlanesFor(camera.position, bounds_, zNear, zFar);
  FrameView view = makeFrameView(camera.position, camera.target, camera.up, camera.fovY,
                                 camera.aspect, zNear, zFar);
  std::vector<const GpuMesh*> meshes;
  meshes.reserve(front.size());
  hlod::Aabb drawn;
  const auto& gl = renderer_->gl();
  for (std::size_t i = 0; i < front.size(); ++i)
    if (GpuMesh* m = residency_.find(front[i])) {
      // Whole unless the selection says otherwise (fewer triangles, or splats).
      m->setDraw(
          gl, draws.empty() ? hlod::NodeDraw{skeleton_.nodes[front[i]].numTri, false} : draws[i]);
      meshes.push_back(m);
      drawn.extend(skeleton_.nodes[front[i]].bounds);
    }
  // The shadow map is fitted to what this frame draws.
  if (!drawn.empty()) {
    view.sceneCentre = drawn.centre();
    view.sceneRadius = std::max(glm::length(drawn.size()) * 0.5, 1e-3);
  }
  const FrameTiming t = renderer_->drawFrame(view, meshes);
  hlod::DrawReport report;
  report.ms = t.cpuMs;
  report.gpuMs = t.gpuMs;
  report.triangles = t.triangles;
  report.drawCalls = t.drawCalls;
  for (const auto& p : t.passes) report.passes.push_back({p.name, p.gpuMs});
  return report;
}

}  // namespace renderer
