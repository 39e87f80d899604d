#pragma once
// The GPU memory manager of Manocha sec. 5.1.3: uploaded nodes stay in GPU memory over frames
// under a byte budget, and the least recently used are replaced first. GL-free: the renderer's
// residency (renderer/GpuResidency) asks it which node to free next and tells it what it
// uploaded, freed and drew.
//
// A node is never chosen while
//  - the last frame drew it (the frame being selected may draw it again: evicting it would
//    trade one node for another every frame instead of drawing coarser),
//  - one of its children is on the GPU (the set on the GPU stays closed upwards, as the
//    selectors need: they reach a node only through its parent), or
//  - it is a root (hlod_0, or the top cell: what every frame falls back to), or
//  - it is a sibling of the node that needs the room: siblings are drawn as a group, and one
//    evicted for another would be uploaded again next frame for the first, forever.
// So a budget below the front's size degrades to coarser drawing: an upload that finds no
// victim waits (the renderer defers it), and the selector draws the parent meanwhile.
#include <cstdint>
#include <span>
#include <vector>

#include "hlod/store/Skeleton.h"

namespace hlod {

class GpuMemoryManager {
 public:
  // budgetBytes 0: no budget (nothing is ever chosen).
  GpuMemoryManager(const Skeleton& skeleton, std::uint64_t budgetBytes);

  std::uint64_t budgetBytes() const { return budget_; }
  void uploaded(std::uint32_t node);
  void freed(std::uint32_t node);
  // After each frame: the nodes it drew.
  void drawn(std::span<const std::uint32_t> front);
  // Whether `bytes` more fit in the budget when `usedBytes` are held now.
  bool fits(std::uint64_t usedBytes, std::uint64_t bytes) const;
  // The node to free next for room for `forNode`: the least recently drawn one that may go
  // (see above); kNoNode when none may.
  std::uint32_t nextVictim(std::uint32_t forNode) const;

 private:
  const Skeleton& skeleton_;
  std::uint64_t budget_;
  std::uint32_t frame_ = 0;
  std::vector<std::uint8_t> onGpu_;
  std::vector<std::uint32_t> childrenOnGpu_;
  std::vector<std::uint32_t> lastDrawn_;  // frame each node was last drawn (0: never)
  std::vector<std::uint32_t> held_;       // the nodes on the GPU
};

}  // namespace hlod
