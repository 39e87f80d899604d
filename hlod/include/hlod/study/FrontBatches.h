#pragma once
// A front larger than memory, drawn in batches: the study's full-detail reference of a
// 100 M-triangle city holds the whole city in one frame (9.4 GB decoded, and as much again as GPU
// copies). The front is split into batches that each fit a byte cap (partitionFront); they are
// drawn one after another into the same frame, depth-tested, so the order changes nothing in the
// image. Between them a residency kept under the cap (CappedResidency) evicts the least recently
// drawn nodes to make room for the next batch's, so that the next frame of a path, drawn with the
// nodes of this one still there where they fit, loads only what is missing (Manocha sec. 5.2:
// the memory footprint is the working set, not the model).
//
// Bytes are what a node holds decoded (NodeInfo::memoryBytes; without its texture when textures
// are off), a texture several nodes share (NodeInfo::textureOffset) once while any holds it.
#include <cstdint>
#include <span>
#include <vector>

#include "hlod/store/Skeleton.h"

namespace hlod::study {

class CappedResidency {
 public:
  // capBytes 0: no cap (everything stays).
  CappedResidency(const Skeleton& skeleton, std::uint64_t capBytes, bool textures);

  struct Change {
    std::vector<std::uint32_t> evict;  // least recently used first
    std::vector<std::uint32_t> load;   // the batch's nodes not resident, in its order
  };
  // Makes `batch` resident: the nodes to evict first, then those to load. Only nodes outside the
  // batch are evicted, least recently used (by ensure) first, until the batch fits; a batch that
  // does not fit on its own (one node larger than the cap) leaves the residency over the cap.
  Change ensure(std::span<const std::uint32_t> batch);
  // Forgets everything (the caller dropped its copies).
  void clear();

  bool isResident(std::uint32_t node) const { return node < stamp_.size() && stamp_[node] != 0; }
  std::uint64_t bytes() const { return bytes_; }
  std::uint64_t peakBytes() const { return peak_; }
  std::uint64_t capBytes() const { return cap_; }
  std::size_t nodes() const { return count_; }
  // Bytes the nodes hold together (a shared texture once).
  std::uint64_t bytesOf(std::span<const std::uint32_t> nodes) const;
  // A node's bytes without its texture, and its texture's (0: none, or textures off).
  std::uint64_t meshBytes(std::uint32_t node) const;
  std::uint64_t textureBytes(std::uint32_t node) const;
  // The node's texture as a small number shared by the nodes that share it; kNoNode: none.
  std::uint32_t textureKey(std::uint32_t node) const { return textureIndex_[node]; }
  bool textures() const { return textures_; }

 private:
  void add(std::uint32_t node);
  void remove(std::uint32_t node);

  const Skeleton& skeleton_;
  std::uint64_t cap_;
  bool textures_;
  std::vector<std::uint64_t> stamp_;  // 0: not resident; else when last in a batch
  std::uint64_t now_ = 0;
  std::vector<std::uint32_t> users_;  // per textureOffset key (textureIndex_), resident users
  std::vector<std::uint32_t> textureIndex_;  // per node: its texture's key, or kNoNode
  std::uint64_t bytes_ = 0, peak_ = 0;
  std::size_t count_ = 0;
};

// Splits front into batches of at most residency.capBytes() bytes each (a shared texture once per
// batch; a node larger than the cap alone in its batch; no cap: one batch). The nodes the
// residency holds come first (drawn without a load, as long as they fit one batch); the others
// follow in front order, nodes sharing a texture kept together.
std::vector<std::vector<std::uint32_t>> partitionFront(std::span<const std::uint32_t> front,
                                                       const CappedResidency& residency);

}  // namespace hlod::study
