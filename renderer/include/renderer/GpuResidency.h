#pragma once
// The GPU copies of one session's resident nodes, keyed by node id, and the queue of loaded
// payloads waiting for an upload. Uploads run on the render thread under a per-frame budget
// (time and bytes), as OpenSceneGraph's incremental compile does; each upload is timed through
// its GL work (GpuMesh::upload finishes it), so the time is the upload's whole cost.
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <unordered_map>
#include <utility>

#include "hlod/runtime/FrameDriver.h"
#include "hlod/runtime/GpuMemoryManager.h"
#include "hlod/runtime/Selector.h"
#include "renderer/GpuMesh.h"

namespace renderer {

class GpuResidency {
 public:
  GpuResidency(const GlFunctions& gl, std::size_t nodeCount) : gl_(gl), onGpu_(nodeCount) {}

  // Queues a payload for upload; nothing when the node is on the GPU or queued already.
  void queue(std::uint32_t node, std::shared_ptr<const hlod::LocalMesh> mesh);
  void evict(std::uint32_t node);
  // Uploads queued payloads in order until budgetMs or budgetBytes (0: no byte limit) is spent,
  // at least one so that uploads always progress. A payload the GL refuses is an Error naming
  // the node (it leaves the queue). With a memory manager, room is made first by freeing the
  // nodes it names; a payload it finds no room for leaves the queue (deferred: queued again
  // when wanted).
  hlod::Result<hlod::UploadReport> upload(double budgetMs, std::uint64_t budgetBytes);
  // The GPU memory budget (nullptr: none); it must outlive this.
  void setMemoryManager(hlod::GpuMemoryManager* manager) { manager_ = manager; }
  // Copies freed to make room since the last call.
  std::uint32_t takeEvictions() { return std::exchange(evictions_, 0u); }
  bool pendingOrOnGpu(std::uint32_t node) const;

  std::size_t pending() const { return pending_.size(); }
  const hlod::ResidencySet& onGpu() const { return onGpu_; }
  const GpuMesh* find(std::uint32_t node) const;
  GpuMesh* find(std::uint32_t node);  // to set what the next frame draws of it
  std::size_t size() const { return gpu_.size(); }
  std::uint64_t gpuBytes() const { return gpuBytes_; }

 private:
  const GlFunctions& gl_;
  std::unordered_map<std::uint32_t, GpuMesh> gpu_;
  hlod::ResidencySet onGpu_;
  // Loaded payloads waiting for an upload, in load order (parents before children).
  std::deque<std::pair<std::uint32_t, std::shared_ptr<const hlod::LocalMesh>>> pending_;
  // The GPU copy of each texture on the GPU, by the image it came from (owner-compared, so a
  // new image at a freed one's address is another key): nodes sharing a texture share it here.
  std::map<std::weak_ptr<const hlod::Image>, std::weak_ptr<const GpuTexture>, std::owner_less<>>
      textures_;
  std::uint64_t gpuBytes_ = 0;       // buffers, and each texture once
  void forget(const GpuMesh& mesh);  // takes its bytes off gpuBytes_
  hlod::GpuMemoryManager* manager_ = nullptr;
  std::uint32_t evictions_ = 0;
};

// Bytes an upload moves to the GL: vertex attributes, indices and the texture (unless it is on
// the GPU already).
std::uint64_t uploadBytesOf(const hlod::LocalMesh& mesh);

}  // namespace renderer
