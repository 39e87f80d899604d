#pragma once
// Eviction (Lakhia III-D keeps memory bounded by unloading the lowest-priority nodes): what to
// unload to make room for a node. The bounds, either or both:
//
//   maxMemory > c_memory * sum over resident nodes of cost      (the paper's bound, optional)
//   residentBytes + bytes of loads in progress <= capBytes       (a hard cap in decoded bytes)
//
// Victims are less important than the node: kept partial buffers first (cheap to drop), then
// resident nodes without resident children, lowest priority first, deeper levels first, never
// hlod_0 and never one the node's drawing depends on (its ancestors and their siblings), nor one
// holding the texture the node will share; a parent whose children all go may go too. A dry run
// first: nothing is taken unless the node then fits. A node larger than the cap less hlod_0
// never fits. hlod/runtime/Loader.h says why. Private to the loader (runtime/Loader.cpp); not
// locked: the Loader calls it under its mutex.
#include <cstdint>
#include <memory>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/store/Skeleton.h"
#include "runtime/loader/LoadSchedule.h"
#include "runtime/loader/NodeMemory.h"
#include "runtime/loader/PartialBuffers.h"
#include "runtime/loader/SharedTextures.h"

namespace hlod {

struct EvictionLimits {
  std::uint64_t capBytes = 0;  // 0: no cap
  double c_memory = 0.0;       // 0: no bound on cost
  double maxMemory = 0.0;
  std::uint64_t rootBytes = 0;  // memoryBytes of hlod_0, resident for good
};

struct EvictionVictim {
  bool resident;  // a resident node; else a kept partial buffer
  double priority;
  std::uint32_t level;
  std::uint32_t node;
};

// What is in memory now.
struct MemoryInUse {
  std::uint64_t bytes = 0;  // resident and in-flight bytes
  double cost = 0.0;        // cost of the resident nodes
};

class Eviction {
 public:
  // The loader's state it reads: all of it outlives the Eviction.
  Eviction(const Skeleton& skeleton, const NodeMemory& memory, const SharedTextures& textures,
           const PartialBuffers& partials, const LoadSchedule& schedule,
           const std::vector<std::shared_ptr<const LocalMesh>>& resident,
           const std::vector<std::uint8_t>& isRoot, const EvictionLimits& limits);

  // Larger than what hlod_0 leaves of the cap: it can never load.
  bool neverFits(std::uint32_t node) const;
  // Whether `node` of `priority` fits with `inUse` once `victims` (filled, in the order to take
  // them: children before their parents) are gone. False, and nothing to take, when it cannot.
  bool makeRoom(std::uint32_t node, double priority, const MemoryInUse& inUse,
                std::vector<EvictionVictim>& victims);

 private:
  bool hasResidentChild(std::uint32_t node) const;

  const Skeleton& skeleton_;
  const NodeMemory& memory_;
  const SharedTextures& textures_;
  const PartialBuffers& partials_;
  const LoadSchedule& schedule_;
  const std::vector<std::shared_ptr<const LocalMesh>>& resident_;
  const std::vector<std::uint8_t>& isRoot_;
  EvictionLimits limits_;
  std::vector<double> below_;  // makeRoom's scratch
};

}  // namespace hlod
