#pragma once
// The study's full-detail reference frames within a memory cap: the `full` selector's front (every
// visible leaf, as if all were resident), drawn in batches that each fit the cap
// (hlod/study/FrontBatches.h), each batch's missing nodes read and uploaded before it is drawn and
// the least recently drawn others freed to make room. The GPU copies are the only copies kept
// (a payload is decoded, uploaded and dropped), so what the cap bounds is what the reference
// holds; a texture several nodes share is read and uploaded once while any of them is held.
// A front that fits the cap is one batch, and the nodes of one frame that fit stay for the next.
// Used by the study runner (service/Study.h).
#include <cstdint>
#include <memory>
#include <unordered_map>

#include "hlod/Result.h"
#include "hlod/metrics/ImageMetrics.h"
#include "hlod/runtime/CameraPath.h"
#include "hlod/runtime/FullSelector.h"
#include "hlod/store/NodeSource.h"
#include "hlod/study/FrontBatches.h"
#include "renderer/GlContext.h"
#include "renderer/GpuMesh.h"
#include "renderer/Renderer.h"

namespace service {

struct BatchedFrame {
  double drawMs = 0.0;  // the frame's GL work, without the loads between batches (approximate)
  std::uint64_t triangles = 0;
  std::size_t nodes = 0;    // the front's
  std::size_t batches = 0;  // batches it was drawn in
  std::size_t loads = 0;    // nodes read for it
};

class BatchedReference {
 public:
  // capBytes: decoded bytes held at most (0: no cap). The context must be current now and at
  // every later call.
  static hlod::Result<std::unique_ptr<BatchedReference>> create(
      std::shared_ptr<const hlod::NodeSource> source, const renderer::RenderOptions& options,
      std::uint64_t capBytes, renderer::GlContext& context);

  hlod::Result<BatchedFrame> render(const hlod::CameraSample& sample);
  hlod::Image readback() { return renderer_->readback(); }
  hlod::metrics::Mask coverage() { return renderer_->coverage(); }
  // The most decoded bytes held at once so far (the cap, unless one node is larger).
  std::uint64_t peakBytes() const { return residency_.peakBytes(); }

 private:
  BatchedReference(std::shared_ptr<const hlod::NodeSource> source, std::uint64_t capBytes,
                   bool textures);
  // Reads, decodes and uploads one node (its texture only when not on the GPU already).
  hlod::Status load(std::uint32_t node);

  std::shared_ptr<const hlod::NodeSource> source_;
  hlod::FullSelector selector_;
  hlod::study::CappedResidency residency_;
  std::unique_ptr<renderer::Renderer> renderer_;
  std::unordered_map<std::uint32_t, renderer::GpuMesh> gpu_;
  // The GPU copy of each texture by its key (CappedResidency::textureKey), while a node uses it.
  std::unordered_map<std::uint32_t, std::weak_ptr<const renderer::GpuTexture>> textures_;
  hlod::Aabb bounds_;  // of the whole model: the clip planes
};

}  // namespace service
