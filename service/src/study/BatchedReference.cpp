// The study's reference frames within a memory cap. See BatchedReference.h.
#include "service/BatchedReference.h"

#include <chrono>
#include <new>

#include "hlod/runtime/FrameDriver.h"
#include "renderer/GpuNodeRenderer.h"

namespace service {

BatchedReference::BatchedReference(std::shared_ptr<const hlod::NodeSource> source,
                                   std::uint64_t capBytes, bool textures)
    : source_(std::move(source)),
      selector_(source_->skeleton()),
      residency_(source_->skeleton(), capBytes, textures) {
  for (std::uint32_t r : source_->skeleton().roots)
    bounds_.extend(source_->skeleton().nodes[r].bounds);
}

hlod::Result<std::unique_ptr<BatchedReference>> BatchedReference::create(
    std::shared_ptr<const hlod::NodeSource> source, const renderer::RenderOptions& options,
    std::uint64_t capBytes, renderer::GlContext& context) {
  if (!source || source->skeleton().roots.empty()) return hlod::makeError("no nodes to draw");
  std::unique_ptr<BatchedReference> r(
      new BatchedReference(std::move(source), capBytes, options.effects.textures));
  auto made = renderer::Renderer::create(context, options);
  if (!made) return made.error();
  r->renderer_ = std::move(*made);
  return r;
}

hlod::Status BatchedReference::load(std::uint32_t node) {
  const hlod::NodeInfo& info = source_->skeleton().nodes[node];
  const std::uint32_t key = residency_.textureKey(node);
  std::shared_ptr<const renderer::GpuTexture> shared;
  if (key != hlod::kNoNode)
    if (auto it = textures_.find(key); it != textures_.end()) shared = it->second.lock();
  // The texture section only when its texture is not on the GPU already (nor left out).
  const bool withTexture = key != hlod::kNoNode && !shared;
  const std::uint64_t size = withTexture ? info.payloadSize : info.meshSize();
  std::vector<std::byte> bytes;
  try {
    bytes.resize(size);
  } catch (const std::bad_alloc&) {
    return hlod::makeError("node " + std::to_string(node) + ": cannot allocate " +
                           std::to_string(size) + " bytes");
  }
  if (auto read = source_->readPayloadChunk(node, 0, bytes); !read) return read.error();
  auto mesh = source_->decodePayload(node, bytes);
  if (!mesh) return mesh.error();
  bytes = {};
  auto gpu = renderer::GpuMesh::upload(renderer_->gl(), *mesh, shared);
  if (!gpu) return hlod::makeError("node " + std::to_string(node) + ": " + gpu.message());
  if (withTexture && gpu->gpuTexture()) textures_[key] = gpu->gpuTexture();
  gpu_.insert_or_assign(node, std::move(*gpu));
  return hlod::Ok{};
}

hlod::Result<BatchedFrame> BatchedReference::render(const hlod::CameraSample& sample) {
  using Clock = std::chrono::steady_clock;
  const hlod::Skeleton& skel = source_->skeleton();
  const renderer::RenderOptions& o = renderer_->options();
  hlod::View view{sample.camera, sample.velocity, o.width, o.height};
  view.camera.aspect = static_cast<double>(o.width) / o.height;
  if (o.effects.fog && o.effects.fog->density > 0.0)
    view.fogCullDistance = hlod::fogCullDistance(o.effects.fog->density);
  const hlod::AllResident all;
  const hlod::Selection selection = selector_.select(view, all);
  const std::vector<std::uint32_t> front =
      hlod::nearToFar(skel, view.camera.position, selection.front);
  const auto batches = hlod::study::partitionFront(front, residency_);

  const hlod::Camera& camera = view.camera;
  double zNear = camera.nearPlane, zFar = camera.farPlane;
  if (!bounds_.empty()) renderer::clipPlanesFor(camera.position, bounds_, zNear, zFar);
  renderer::FrameView frameView = renderer::makeFrameView(camera.position, camera.target, camera.up,
                                                          camera.fovY, camera.aspect, zNear, zFar);
  hlod::Aabb drawn;
  for (std::uint32_t n : front) drawn.extend(skel.nodes[n].bounds);
  // The shadow map's fit: the whole front, which is never at hand at once.
  frameView.sceneCentre = drawn.empty() ? bounds_.centre() : drawn.centre();
  frameView.sceneRadius =
      std::max(glm::length((drawn.empty() ? bounds_ : drawn).size()) * 0.5, 1e-3);

  BatchedFrame frame;
  frame.nodes = front.size();
  frame.batches = batches.size();
  hlod::Status failed = hlod::Ok{};
  double loadMs = 0.0;
  const auto part = [&](std::size_t k) {
    const auto start = Clock::now();
    std::vector<const renderer::GpuMesh*> meshes;
    const auto change = residency_.ensure(batches[k]);
    for (std::uint32_t n : change.evict) gpu_.erase(n);
    for (std::uint32_t n : change.load) {
      if (!failed) break;
      failed = load(n);
      ++frame.loads;
    }
    if (textures_.size() > 2 * gpu_.size() + 16)
      std::erase_if(textures_, [](const auto& t) { return t.second.expired(); });
    for (std::uint32_t n : batches[k])
      if (auto it = gpu_.find(n); it != gpu_.end()) {
        it->second.setDraw(renderer_->gl(), hlod::NodeDraw{skel.nodes[n].numTri, false});
        meshes.push_back(&it->second);
      }
    loadMs += std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return meshes;
  };
  const renderer::FrameTiming timing = renderer_->drawFrameInParts(frameView, batches.size(), part);
  if (!failed) {
    // What was loaded is gone from the residency's view too: start over next frame.
    gpu_.clear();
    textures_.clear();
    residency_.clear();
    return failed.error();
  }
  frame.drawMs = std::max(0.0, timing.cpuMs - loadMs);
  frame.triangles = timing.triangles;
  return frame;
}

}  // namespace service
