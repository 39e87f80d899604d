#pragma once
// What a node costs the loader in bytes: what a load of it reads and what it holds decoded,
// without its texture section when the scene declares no textures (LoaderParams::textures), and
// less its texture when that is shared and held already (SharedTextures.h). Private to the loader.
#include <cstdint>

#include "hlod/store/Skeleton.h"
#include "runtime/loader/SharedTextures.h"

namespace hlod {

class NodeMemory {
 public:
  NodeMemory(const Skeleton& skeleton, bool textures) : skeleton_(skeleton), textures_(textures) {}

  // The bytes a load of the node reads.
  std::uint64_t readSize(std::uint32_t node) const {
    const NodeInfo& n = skeleton_.nodes[node];
    return textures_ ? n.payloadSize : n.payloadSize - n.textureSize;
  }
  // The bytes the node holds decoded.
  std::uint64_t memory(std::uint32_t node) const {
    const NodeInfo& n = skeleton_.nodes[node];
    return textures_ ? n.memoryBytes : n.memoryBytes - n.textureBytes;
  }
  // The node has a texture this loader keeps.
  bool hasTexture(std::uint32_t node) const {
    return textures_ && skeleton_.nodes[node].textureSize > 0;
  }
  // Its texture is held already (shared with a resident node or a load in progress).
  bool textureHeld(std::uint32_t node, const SharedTextures& shared) const {
    return hasTexture(node) && shared.held(skeleton_.nodes[node].textureOffset);
  }
  // What loading the node adds to memory: its decoded bytes, less a texture held already.
  std::uint64_t charge(std::uint32_t node, const SharedTextures& shared) const {
    const NodeInfo& n = skeleton_.nodes[node];
    return textureHeld(node, shared) ? n.memoryBytes - n.textureBytes : memory(node);
  }

 private:
  const Skeleton& skeleton_;
  bool textures_;
};

}  // namespace hlod
