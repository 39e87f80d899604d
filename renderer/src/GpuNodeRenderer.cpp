#include "renderer/GpuNodeRenderer.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace renderer {

void GpuNodeRenderer::setGpuBudget(std::uint64_t bytes) {
  residency_.setMemoryManager(nullptr);
  memory_.reset();
  if (bytes == 0) return;
  memory_ = std::make_unique<hlod::GpuMemoryManager>(skeleton_, bytes);
  for (std::uint32_t n = 0; n < skeleton_.nodes.size(); ++n)
    if (residency_.onGpu().isResident(n)) memory_->uploaded(n);
  residency_.setMemoryManager(memory_.get());
}

std::vector<hlod::OcclusionResult> GpuNodeRenderer::occlusionResults() {
  std::vector<hlod::OcclusionResult> out;
  if (answersTaken_) return out;
  answersTaken_ = true;
  const Renderer::OcclusionAnswers a = renderer_->occlusionAnswers();
  assert(a.queriedMeshes.size() == a.meshSamples.size());
  for (std::size_t k = 0; k < a.queriedMeshes.size(); ++k) {
    assert(a.queriedMeshes[k] < meshNodes_.size());
    hlod::OcclusionResult r;
    r.nodes = {meshNodes_[a.queriedMeshes[k]]};
    r.answered = a.meshSamples[k].has_value();
    r.samples = a.meshSamples[k].value_or(0);
    out.push_back(std::move(r));
  }
  for (std::size_t k = 0; k < batchNodes_.size(); ++k) {
    hlod::OcclusionResult r;
    r.nodes = batchNodes_[k];
    r.answered = k < a.boxSamples.size() && a.boxSamples[k].has_value();
    r.samples = r.answered ? *a.boxSamples[k] : 0;
    out.push_back(std::move(r));
  }
  for (std::uint32_t n : unqueried_) out.push_back({{n}, 0, false});
  return out;
}

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
                                                     std::span<const hlod::NodeDraw> draws,
                                                     const hlod::OcclusionPlan* occlusion) {
  assert(!occlusion || occlusion->queryDraw.size() == front.size());
  double zNear = camera.nearPlane, zFar = camera.farPlane;
  if (!bounds_.empty()) clipPlanesFor(camera.position, bounds_, zNear, zFar);
  FrameView view = makeFrameView(camera.position, camera.target, camera.up, camera.fovY,
                                 camera.aspect, zNear, zFar);
  // A box that reaches the near plane (or holds the eye) cannot be tested: clipped, it could
  // read hidden while it is not. Such a node is not queried and counts as visible.
  const glm::dvec3 forward = camera.forward();
  auto reachesNear = [&](const hlod::Aabb& b) {
    const glm::dvec3 nearest(forward.x >= 0.0 ? b.min.x : b.max.x,
                             forward.y >= 0.0 ? b.min.y : b.max.y,
                             forward.z >= 0.0 ? b.min.z : b.max.z);
    return glm::dot(nearest - camera.position, forward) <= zNear * 1.01;
  };
  batchNodes_.clear();
  unqueried_.clear();
  std::vector<const GpuMesh*> meshes;
  std::vector<std::uint8_t> queryMesh;
  meshes.reserve(front.size());
  meshNodes_.clear();
  hlod::Aabb drawn;
  const auto& gl = renderer_->gl();
  for (std::size_t i = 0; i < front.size(); ++i)
    if (GpuMesh* m = residency_.find(front[i])) {
      // Whole unless the selection says otherwise (fewer triangles, or splats).
      m->setDraw(
          gl, draws.empty() ? hlod::NodeDraw{skeleton_.nodes[front[i]].numTri, false} : draws[i]);
      meshes.push_back(m);
      meshNodes_.push_back(front[i]);
      if (occlusion) {
        const bool untestable = occlusion->queryDraw[i] && reachesNear(skeleton_.nodes[front[i]].bounds);
        if (untestable) unqueried_.push_back(front[i]);
        queryMesh.push_back(occlusion->queryDraw[i] && !untestable);
      }
      drawn.extend(skeleton_.nodes[front[i]].bounds);
    }
  // The shadow map is fitted to what this frame draws.
  if (!drawn.empty()) {
    view.sceneCentre = drawn.centre();
    view.sceneRadius = std::max(glm::length(drawn.size()) * 0.5, 1e-3);
  }
  // The boxes of hidden nodes, by batch. Hidden nodes on the GPU still cast shadows onto what
  // is seen.
  std::vector<std::vector<hlod::Aabb>> boxBatches;
  std::vector<const GpuMesh*> hiddenCasters;
  std::vector<hlod::Aabb> tint;
  if (occlusion) {
    for (const auto& batch : occlusion->boxBatches) {
      std::vector<std::uint32_t> nodes;
      std::vector<hlod::Aabb> boxes;
      for (std::uint32_t n : batch) {
        const hlod::Aabb& b = skeleton_.nodes[n].bounds;
        if (reachesNear(b)) {
          unqueried_.push_back(n);
          continue;
        }
        nodes.push_back(n);
        boxes.push_back(b);
        if (const GpuMesh* m = residency_.find(n)) hiddenCasters.push_back(m);
        if (showOcclusion_) tint.push_back(b);
      }
      if (nodes.empty()) continue;
      batchNodes_.push_back(std::move(nodes));
      boxBatches.push_back(std::move(boxes));
    }
  }
  const OcclusionDraw od{queryMesh, boxBatches, hiddenCasters, tint};
  const FrameTiming t = renderer_->drawFrame(view, meshes, occlusion ? &od : nullptr);
  if (memory_) memory_->drawn(meshNodes_);
  answersTaken_ = occlusion == nullptr;
  hlod::DrawReport report;
  report.ms = t.cpuMs;
  report.gpuMs = t.gpuMs;
  report.triangles = t.triangles;
  report.drawCalls = t.drawCalls;
  for (const auto& p : t.passes) report.passes.push_back({p.name, p.gpuMs});
  return report;
}

}  // namespace renderer
