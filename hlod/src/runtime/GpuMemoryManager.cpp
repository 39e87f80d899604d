// The GPU memory manager (Manocha sec. 5.1.3): see hlod/runtime/GpuMemoryManager.h.
#include "hlod/runtime/GpuMemoryManager.h"

#include <algorithm>
#include <cassert>

namespace hlod {

GpuMemoryManager::GpuMemoryManager(const Skeleton& skeleton, std::uint64_t budgetBytes)
    : skeleton_(skeleton),
      budget_(budgetBytes),
      onGpu_(skeleton.nodes.size(), 0),
      childrenOnGpu_(skeleton.nodes.size(), 0),
      lastDrawn_(skeleton.nodes.size(), 0) {}

void GpuMemoryManager::uploaded(std::uint32_t node) {
  assert(node < onGpu_.size());
  if (onGpu_[node]) return;
  onGpu_[node] = 1;
  held_.push_back(node);
  const std::uint32_t p = skeleton_.nodes[node].parent;
  if (p != kNoNode) ++childrenOnGpu_[p];
}

void GpuMemoryManager::freed(std::uint32_t node) {
  assert(node < onGpu_.size());
  if (!onGpu_[node]) return;
  onGpu_[node] = 0;
  std::erase(held_, node);
  const std::uint32_t p = skeleton_.nodes[node].parent;
  if (p != kNoNode) {
    assert(childrenOnGpu_[p] > 0);
    --childrenOnGpu_[p];
  }
}

void GpuMemoryManager::drawn(std::span<const std::uint32_t> front) {
  ++frame_;
  for (std::uint32_t n : front) lastDrawn_[n] = frame_;
}

bool GpuMemoryManager::fits(std::uint64_t usedBytes, std::uint64_t bytes) const {
  return budget_ == 0 || (bytes <= budget_ && usedBytes <= budget_ - bytes);
}

std::uint32_t GpuMemoryManager::nextVictim(std::uint32_t forNode) const {
  if (budget_ == 0) return kNoNode;
  assert(forNode < skeleton_.nodes.size());
  const std::uint32_t group = skeleton_.nodes[forNode].parent;
  std::uint32_t best = kNoNode;
  for (std::uint32_t n : held_) {
    const NodeInfo& info = skeleton_.nodes[n];
    if (info.parent == kNoNode || childrenOnGpu_[n] > 0 || info.parent == group) continue;
    if (frame_ > 0 && lastDrawn_[n] == frame_) continue;
    if (best == kNoNode || lastDrawn_[n] < lastDrawn_[best] ||
        (lastDrawn_[n] == lastDrawn_[best] && info.level > skeleton_.nodes[best].level))
      best = n;
  }
  return best;
}

}  // namespace hlod
