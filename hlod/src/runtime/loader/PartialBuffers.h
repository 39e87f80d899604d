#pragma once
// The read buffers of loads in progress (Lakhia III-D: a load goes a chunk at a time, so that it
// can be pre-empted between chunks). A buffer stays when a more important node pre-empts its load
// (LoaderParams::keepPartial), so that the load resumes where it stopped if that node comes back;
// at most LoaderParams::maxPartials are kept, the least important going first. Private to the
// loader (runtime/Loader.cpp), which accounts for their bytes; not locked: the Loader calls it
// under its mutex.
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "hlod/store/Skeleton.h"

namespace hlod {

struct PartialLoad {
  std::vector<std::byte> bytes;
  std::uint64_t filled = 0;
  std::uint64_t reserved = 0;  // its bytes in LoaderCounters::inFlightBytes
  bool textureHeld = false;    // reads the mesh section only: its texture is held already
  bool cacheReserved = false;  // its memoryBytes are reserved in LoaderParams::cache
};

class PartialBuffers {
 public:
  // The node's buffer, null when it has none. Stays valid until take(node).
  PartialLoad* find(std::uint32_t node) const;
  bool contains(std::uint32_t node) const { return loads_.count(node) > 0; }
  std::size_t size() const { return loads_.size(); }
  // Keeps a new buffer for a node that has none.
  PartialLoad& add(std::uint32_t node, std::unique_ptr<PartialLoad> load);
  // Removes the node's buffer and hands it over (null when it has none).
  std::unique_ptr<PartialLoad> take(std::uint32_t node);

  // The buffer to drop when too many are kept: the least important by priority(node) other than
  // `keep`, the lowest node index among equals; kNoNode when there is none.
  template <class Priority>
  std::uint32_t leastImportantOther(std::uint32_t keep, Priority&& priority) const;

  // In ascending node order.
  auto begin() const { return loads_.begin(); }
  auto end() const { return loads_.end(); }

 private:
  std::map<std::uint32_t, std::unique_ptr<PartialLoad>> loads_;
};

template <class Priority>
std::uint32_t PartialBuffers::leastImportantOther(std::uint32_t keep, Priority&& priority) const {
  std::uint32_t worst = kNoNode;
  double worstP = 0.0;
  for (const auto& [n, load] : loads_) {
    if (n == keep) continue;
    const double p = priority(n);
    if (worst == kNoNode || p < worstP) {
      worst = n;
      worstP = p;
    }
  }
  return worst;
}

}  // namespace hlod
