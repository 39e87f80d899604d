#include "renderer/GpuResidency.h"

#include <algorithm>
#include <chrono>

namespace renderer {

std::uint64_t uploadBytesOf(const hlod::LocalMesh& m) {
  std::uint64_t b = m.positions.size() * 12 + m.normals.size() * 12 + m.texCoords.size() * 8 +
                    m.indices.size() * 4 + m.splats.size() * sizeof(hlod::Splat);
  if (m.texture) b += static_cast<std::uint64_t>(m.texture->pixels.size());
  return b;
}

bool GpuResidency::pendingOrOnGpu(std::uint32_t node) const {
  return onGpu_.isResident(node) || std::any_of(pending_.begin(), pending_.end(),
                                                [&](const auto& p) { return p.first == node; });
}

void GpuResidency::queue(std::uint32_t node, std::shared_ptr<const hlod::LocalMesh> mesh) {
  if (pendingOrOnGpu(node)) return;
  pending_.emplace_back(node, std::move(mesh));
}

void GpuResidency::forget(const GpuMesh& mesh) {
  gpuBytes_ -= mesh.gpuBytes();
  // The last mesh drawn with a texture takes it off the GPU.
  if (const auto& t = mesh.gpuTexture(); t && t.use_count() == 1) gpuBytes_ -= t->gpuBytes;
  if (textures_.size() > 2 * gpu_.size() + 16)
    std::erase_if(textures_, [](const auto& e) { return e.second.expired(); });
}

void GpuResidency::evict(std::uint32_t node) {
  if (auto it = gpu_.find(node); it != gpu_.end()) {
    forget(it->second);
    gpu_.erase(it);
  }
  onGpu_.set(node, false);
  if (manager_) manager_->freed(node);
  std::erase_if(pending_, [&](const auto& p) { return p.first == node; });
}

const GpuMesh* GpuResidency::find(std::uint32_t node) const {
  auto it = gpu_.find(node);
  return it == gpu_.end() ? nullptr : &it->second;
}

GpuMesh* GpuResidency::find(std::uint32_t node) {
  auto it = gpu_.find(node);
  return it == gpu_.end() ? nullptr : &it->second;
}

hlod::Result<hlod::UploadReport> GpuResidency::upload(double budgetMs, std::uint64_t budgetBytes) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto elapsedMs = [&] {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  };
  hlod::UploadReport report;
  while (!pending_.empty()) {
    if (report.uploads > 0 &&
        (elapsedMs() >= budgetMs || (budgetBytes > 0 && report.bytes >= budgetBytes)))
      break;
    auto [node, mesh] = std::move(pending_.front());
    pending_.pop_front();
    std::shared_ptr<const GpuTexture> shared;
    if (mesh->texture)
      if (auto it = textures_.find(mesh->texture); it != textures_.end())
        shared = it->second.lock();
    const bool fresh = !shared;
    if (manager_) {
      // Room first, least recently drawn out; none to be had: the upload waits (the selector
      // draws the parent meanwhile, and queues it again while it wants it).
      const std::uint64_t bytes =
          uploadBytesOf(*mesh) - (fresh || !mesh->texture ? 0 : mesh->texture->pixels.size());
      std::uint32_t victim = hlod::kNoNode;
      while (!manager_->fits(gpuBytes_, bytes) &&
             (victim = manager_->nextVictim(node)) != hlod::kNoNode) {
        evict(victim);
        ++evictions_;
      }
      if (!manager_->fits(gpuBytes_, bytes)) {
        ++report.deferred;
        continue;
      }
    }
    auto gpu = GpuMesh::upload(gl_, mesh, shared);
    if (!gpu) return hlod::makeError("node " + std::to_string(node) + ": " + gpu.message());
    if (fresh && gpu->gpuTexture()) {
      textures_.insert_or_assign(mesh->texture, gpu->gpuTexture());
      gpuBytes_ += gpu->gpuTexture()->gpuBytes;
    }
    gpuBytes_ += gpu->gpuBytes();
    if (auto old = gpu_.find(node); old != gpu_.end()) forget(old->second);
    gpu_.insert_or_assign(node, std::move(*gpu));
    onGpu_.set(node, true);
    if (manager_) manager_->uploaded(node);
    ++report.uploads;
    report.bytes +=
        uploadBytesOf(*mesh) - (fresh || !mesh->texture ? 0 : mesh->texture->pixels.size());
  }
  report.ms = elapsedMs();
  return report;
}

}  // namespace renderer
