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
  return std::exchange(answers_, {});
}

void GpuNodeRenderer::collectAnswers() {
  // Right after the frame's glFinish every result is there: reading it costs no wait. The
  // FrameDriver uses them for the next frame.
  std::vector<hlod::OcclusionResult>& out = answers_;
  out.clear();
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

bool GpuNodeRenderer::reachesNear(const hlod::Aabb& b) const {
  // A box that reaches the near plane (or holds the eye) cannot be tested: clipped, it could
  // read hidden while it is not. Such a node is not queried and counts as visible.
  const glm::dvec3 nearest(forward_.x >= 0.0 ? b.min.x : b.max.x,
                           forward_.y >= 0.0 ? b.min.y : b.max.y,
                           forward_.z >= 0.0 ? b.min.z : b.max.z);
  return glm::dot(nearest - eye_, forward_) <= zNear_ * 1.01;
}

std::vector<std::uint8_t> GpuNodeRenderer::queryBoxesOnLastDraw(
    std::span<const std::uint32_t> nodes) {
  std::vector<std::vector<hlod::Aabb>> batches;
  std::vector<std::size_t> at;  // per batch, the node's position
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const hlod::Aabb& box = skeleton_.nodes[nodes[k]].bounds;
    if (reachesNear(box)) continue;
    batches.push_back({box});
    at.push_back(k);
  }
  std::vector<std::uint8_t> visible(nodes.size(), 1);
  const auto samples = renderer_->queryBoxesOnLastFrame(setup_.view, batches);
  // An answer that did not come (it cannot after the wait) counts as visible too.
  for (std::size_t b = 0; b < at.size() && b < samples.size(); ++b)
    visible[at[b]] = !samples[b] || *samples[b] > 0;
  return visible;
}

void GpuNodeRenderer::setUp(const hlod::Camera& camera, std::span<const std::uint32_t> front,
                            std::span<const hlod::NodeDraw> draws,
                            const hlod::OcclusionPlan* occlusion) {
  assert(!occlusion || occlusion->queryDraw.size() == front.size());
  assert(draws.empty() || draws.size() == front.size());
  double zNear = camera.nearPlane, zFar = camera.farPlane;
  if (!bounds_.empty()) clipPlanesFor(camera.position, bounds_, zNear, zFar);
  zNear_ = zNear;
  eye_ = camera.position;
  forward_ = camera.forward();
  FrameSetup& f = setup_;
  f = FrameSetup{};
  f.view = makeFrameView(camera.position, camera.target, camera.up, camera.fovY, camera.aspect,
                         zNear, zFar);
  f.front.assign(front.begin(), front.end());
  f.draws.assign(draws.begin(), draws.end());
  if (occlusion) f.queryDraw = occlusion->queryDraw;
  batchNodes_.clear();
  unqueried_.clear();
  meshNodes_.clear();
  // The shadow map is fitted to what this frame draws.
  hlod::Aabb drawn;
  for (std::uint32_t n : front)
    if (residency_.find(n)) drawn.extend(skeleton_.nodes[n].bounds);
  if (!drawn.empty()) {
    f.view.sceneCentre = drawn.centre();
    f.view.sceneRadius = std::max(glm::length(drawn.size()) * 0.5, 1e-3);
  }
  // The boxes of hidden nodes, by batch. Hidden nodes on the GPU still cast shadows onto what
  // is seen.
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
        if (const GpuMesh* m = residency_.find(n)) f.hiddenCasters.push_back(m);
        if (showOcclusion_) f.tint.push_back(b);
      }
      if (nodes.empty()) continue;
      batchNodes_.push_back(std::move(nodes));
      f.boxBatches.push_back(std::move(boxes));
    }
    f.occlusionDraw = OcclusionDraw{{}, f.boxBatches, f.hiddenCasters, f.tint};
    f.hasOcclusion = true;
  }
}

const GpuMesh* GpuNodeRenderer::meshFor(std::size_t i, std::vector<std::uint8_t>& queryMesh) {
  const std::uint32_t node = setup_.front[i];
  GpuMesh* m = residency_.find(node);
  if (!m) return nullptr;
  // Whole unless the selection says otherwise (fewer triangles, or splats).
  m->setDraw(renderer_->gl(), setup_.draws.empty()
                                  ? hlod::NodeDraw{skeleton_.nodes[node].numTri, false}
                                  : setup_.draws[i]);
  meshNodes_.push_back(node);
  if (setup_.hasOcclusion) {
    const bool wanted = setup_.queryDraw[i] != 0;
    const bool untestable = wanted && reachesNear(skeleton_.nodes[node].bounds);
    if (untestable) unqueried_.push_back(node);
    queryMesh.push_back(wanted && !untestable);
  }
  return m;
}

hlod::DrawReport GpuNodeRenderer::report(const FrameTiming& t) const {
  hlod::DrawReport r;
  r.ms = t.cpuMs;
  r.gpuMs = t.gpuMs;
  r.triangles = t.triangles;
  r.drawCalls = t.drawCalls;
  for (const auto& p : t.passes) r.passes.push_back({p.name, p.gpuMs});
  return r;
}

hlod::Result<hlod::DrawReport> GpuNodeRenderer::draw(const hlod::Camera& camera,
                                                     std::span<const std::uint32_t> front,
                                                     std::span<const hlod::NodeDraw> draws,
                                                     const hlod::OcclusionPlan* occlusion) {
  setUp(camera, front, draws, occlusion);
  std::vector<const GpuMesh*> meshes;
  std::vector<std::uint8_t> queryMesh;
  meshes.reserve(front.size());
  for (std::size_t i = 0; i < front.size(); ++i)
    if (const GpuMesh* m = meshFor(i, queryMesh)) meshes.push_back(m);
  setup_.occlusionDraw.queryMesh = queryMesh;
  const FrameTiming t = renderer_->drawFrame(setup_.view, meshes,
                                             setup_.hasOcclusion ? &setup_.occlusionDraw : nullptr);
  if (memory_) memory_->drawn(meshNodes_);
  if (setup_.hasOcclusion) collectAnswers();
  return report(t);
}

hlod::Result<VisibleCount> GpuNodeRenderer::countVisible(const hlod::Camera& camera,
                                                         std::span<const std::uint32_t> nodes,
                                                         std::span<const hlod::NodeDraw> draws) {
  if (!idBuffer_) {
    auto b =
        IdBuffer::create(renderer_->gl(), renderer_->options().width, renderer_->options().height);
    if (!b) return b.error();
    idBuffer_ = std::move(*b);
  }
  double zNear = camera.nearPlane, zFar = camera.farPlane;
  if (!bounds_.empty()) clipPlanesFor(camera.position, bounds_, zNear, zFar);
  const FrameView view = makeFrameView(camera.position, camera.target, camera.up, camera.fovY,
                                       camera.aspect, zNear, zFar);
  std::vector<const GpuMesh*> meshes;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (GpuMesh* m = residency_.find(nodes[i])) {
      m->setDraw(renderer_->gl(), draws.empty()
                                      ? hlod::NodeDraw{skeleton_.nodes[nodes[i]].numTri, false}
                                      : draws[i]);
      meshes.push_back(m);
    }
  return idBuffer_->count(view, meshes);
}

hlod::Status GpuNodeRenderer::beginParts(const hlod::Camera& camera,
                                         std::span<const std::uint32_t> front,
                                         std::span<const hlod::NodeDraw> draws,
                                         const hlod::OcclusionPlan* occlusion) {
  if (!renderer_->canDrawInParts()) return hlod::makeError("a shadow pass needs the whole front");
  setUp(camera, front, draws, occlusion);
  renderer_->beginParts(setup_.view, setup_.hasOcclusion ? &setup_.occlusionDraw : nullptr);
  return hlod::Ok{};
}

hlod::Status GpuNodeRenderer::drawPart(std::span<const std::size_t> positions) {
  std::vector<const GpuMesh*> meshes;
  std::vector<std::uint8_t> queryMesh;
  for (std::size_t i : positions) {
    if (i >= setup_.front.size()) return hlod::makeError("part position outside the front");
    const GpuMesh* m = meshFor(i, queryMesh);
    if (!m)
      return hlod::makeError("node " + std::to_string(setup_.front[i]) + " is not on the GPU");
    meshes.push_back(m);
  }
  renderer_->drawPart(setup_.view, meshes, queryMesh);
  return hlod::Ok{};
}

hlod::Result<hlod::DrawReport> GpuNodeRenderer::endParts() {
  const FrameTiming t = renderer_->endParts(setup_.view);
  if (memory_) memory_->drawn(meshNodes_);
  if (setup_.hasOcclusion) collectAnswers();
  return report(t);
}

}  // namespace renderer
