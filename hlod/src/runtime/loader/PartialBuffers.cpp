// The read buffers of loads in progress (runtime/loader/PartialBuffers.h).
#include "runtime/loader/PartialBuffers.h"

#include <cassert>
#include <utility>

namespace hlod {

PartialLoad* PartialBuffers::find(std::uint32_t node) const {
  auto it = loads_.find(node);
  return it != loads_.end() ? it->second.get() : nullptr;
}

PartialLoad& PartialBuffers::add(std::uint32_t node, std::unique_ptr<PartialLoad> load) {
  auto [it, fresh] = loads_.emplace(node, std::move(load));
  assert(fresh);
  (void)fresh;
  return *it->second;
}

std::unique_ptr<PartialLoad> PartialBuffers::take(std::uint32_t node) {
  auto it = loads_.find(node);
  if (it == loads_.end()) return nullptr;
  std::unique_ptr<PartialLoad> load = std::move(it->second);
  loads_.erase(it);
  return load;
}

}  // namespace hlod
