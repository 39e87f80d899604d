#pragma once
// Test helpers for the runtime (selectors, loader, camera paths): a synthetic city skeleton laid
// out like the city generator's (blocks on a street grid, Z up, metres, Lakhia-style pieces cut
// along the longest side) and an in-memory NodeSource serving deterministic payloads.
#include <atomic>
#include <cmath>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "hlod/runtime/Camera.h"
#include "hlod/store/NodeSource.h"
#include "hlod/store/Skeleton.h"

namespace hlod::test {

struct SyntheticCity {
  int blocksX = 4;
  int blocksY = 4;
  double blockSize = 40.0;  // metres, square blocks
  double street = 12.0;     // gap between blocks
  double height = 20.0;
  int depth = 3;  // levels below hlod_0
  std::uint32_t levelFactor = 3;
  std::uint32_t triPerNode = 1000;
  std::uint32_t minTri = 0;      // > 0: every node has a progression down to this (a parry store)
  std::uint32_t splatCount = 0;  // splats per node
  std::uint64_t bytesPerTri = 48;
};

// Builds the skeleton breadth-first so that children are contiguous.
inline Skeleton makeSyntheticCity(const SyntheticCity& c) {
  Skeleton sk;
  sk.params.levelFactor = c.levelFactor;
  sk.params.desiredTri = c.triPerNode;
  auto makeNode = [&](const Aabb& box, std::uint32_t level, std::uint32_t block,
                      std::uint32_t parent, std::uint64_t& offset) {
    NodeInfo n;
    n.parent = parent;
    n.level = level;
    n.block = block;
    n.bounds = box;
    n.centre = box.centre();
    n.numTri = c.triPerNode;
    n.minTri = c.minTri;
    n.splatCount = c.splatCount;
    n.cost = c.triPerNode;
    const glm::dvec3 s = box.size();
    const double area = 2.0 * (s.x * s.z + s.y * s.z) + s.x * s.y;
    n.staticBenefit = std::sqrt(n.numTri * area);
    // Facades face along +-Y alternately per block (blocks face their street).
    n.avgNormal = glm::vec3(0.0f, (block % 2) ? 1.0f : -1.0f, 0.0f);
    n.geometricError =
        level >= static_cast<std::uint32_t>(c.depth) ? 0.0 : glm::length(s) / c.levelFactor;
    n.payloadSize = n.numTri * c.bytesPerTri;
    n.memoryBytes = 2 * n.payloadSize;  // as if stored deflated to half
    n.payloadOffset = offset;
    offset += n.payloadSize;
    return n;
  };
  std::uint64_t offset = 0;
  std::uint32_t block = 0;
  for (int j = 0; j < c.blocksY; ++j) {
    for (int i = 0; i < c.blocksX; ++i, ++block) {
      Aabb box;
      box.min = {i * (c.blockSize + c.street), j * (c.blockSize + c.street), 0.0};
      box.max = box.min + glm::dvec3(c.blockSize, c.blockSize, c.height);
      sk.roots.push_back(static_cast<std::uint32_t>(sk.nodes.size()));
      sk.nodes.push_back(makeNode(box, 0, block, kNoNode, offset));
    }
  }
  for (std::uint32_t n = 0; n < sk.nodes.size(); ++n) {
    if (sk.nodes[n].level >= static_cast<std::uint32_t>(c.depth)) continue;
    const Aabb box = sk.nodes[n].bounds;
    const glm::dvec3 s = box.size();
    const int axis = s.x >= s.y ? 0 : 1;
    sk.nodes[n].firstChild = static_cast<std::uint32_t>(sk.nodes.size());
    sk.nodes[n].childCount = c.levelFactor;
    for (std::uint32_t k = 0; k < c.levelFactor; ++k) {
      Aabb piece = box;
      piece.min[axis] = box.min[axis] + s[axis] * k / c.levelFactor;
      piece.max[axis] = box.min[axis] + s[axis] * (k + 1) / c.levelFactor;
      sk.nodes.push_back(makeNode(piece, sk.nodes[n].level + 1, sk.nodes[n].block, n, offset));
    }
  }
  return sk;
}

inline std::byte payloadByte(std::uint32_t node, std::uint64_t i) {
  return static_cast<std::byte>((node * 131u + i * 7u) & 0xffu);
}

// Serves payloads whose bytes follow payloadByte(); decodePayload checks every byte and returns a
// LocalMesh with numTri triangles. Counts chunk reads per node (thread-safe).
class MemoryNodeSource final : public NodeSource {
 public:
  explicit MemoryNodeSource(Skeleton skeleton)
      : skeleton_(std::move(skeleton)), reads_(skeleton_.nodes.size()) {}

  const Skeleton& skeleton() const override { return skeleton_; }

  Status readPayloadChunk(std::uint32_t node, std::uint64_t offset,
                          std::span<std::byte> out) const override {
    if (node >= skeleton_.nodes.size()) return makeError("node out of range");
    const std::uint64_t size = skeleton_.nodes[node].payloadSize;
    if (offset > size || out.size() > size - offset) return makeError("range outside payload");
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = payloadByte(node, offset + i);
    reads_[node].fetch_add(1);
    {
      std::lock_guard lock(mutex_);
      readLog_.push_back(node);
    }
    return Ok{};
  }

  Result<LocalMesh> decodePayload(std::uint32_t node,
                                  std::span<const std::byte> bytes) const override {
    if (node >= skeleton_.nodes.size()) return makeError("node out of range");
    if (bytes.size() != skeleton_.nodes[node].payloadSize) return makeError("size mismatch");
    for (std::size_t i = 0; i < bytes.size(); ++i) {
      if (bytes[i] != payloadByte(node, i)) return makeError("checksum mismatch");
    }
    LocalMesh m;
    m.centre = skeleton_.nodes[node].centre;
    m.positions.assign(3, glm::vec3(0.0f));
    m.normals.assign(3, glm::vec3(0.0f, 0.0f, 1.0f));
    m.indices.assign(std::size_t(skeleton_.nodes[node].numTri) * 3, 0u);
    return m;
  }

  int reads(std::uint32_t node) const { return reads_[node].load(); }
  std::vector<std::uint32_t> readLog() const {
    std::lock_guard lock(mutex_);
    return readLog_;
  }

 private:
  Skeleton skeleton_;
  mutable std::vector<std::atomic<int>> reads_;
  mutable std::mutex mutex_;
  mutable std::vector<std::uint32_t> readLog_;
};

// A view of the whole skeleton from above and in front, 60 degrees wide.
inline View overview(const Skeleton& sk) {
  Aabb all;
  for (std::uint32_t r : sk.roots) all.extend(sk.nodes[r].bounds);
  View v;
  v.camera.target = all.centre();
  v.camera.position = all.centre() + glm::dvec3(0.0, -0.8, 0.6) * glm::length(all.size());
  v.camera.fovY = 60.0;
  return v;
}

}  // namespace hlod::test
