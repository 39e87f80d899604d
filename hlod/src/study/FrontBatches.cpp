// A front drawn in batches under a memory cap (hlod/study/FrontBatches.h).
#include "hlod/study/FrontBatches.h"

#include <algorithm>
#include <cassert>
#include <unordered_map>
#include <unordered_set>

namespace hlod::study {

CappedResidency::CappedResidency(const Skeleton& skeleton, std::uint64_t capBytes, bool textures)
    : skeleton_(skeleton),
      cap_(capBytes),
      textures_(textures),
      stamp_(skeleton.nodes.size(), 0),
      textureIndex_(skeleton.nodes.size(), kNoNode) {
  if (!textures_) return;
  std::unordered_map<std::uint64_t, std::uint32_t> key;
  for (std::uint32_t n = 0; n < skeleton.nodes.size(); ++n) {
    const NodeInfo& info = skeleton.nodes[n];
    if (info.textureSize == 0) continue;
    textureIndex_[n] = key.try_emplace(info.textureOffset, std::uint32_t(key.size())).first->second;
  }
  users_.assign(key.size(), 0);
}

std::uint64_t CappedResidency::meshBytes(std::uint32_t node) const {
  const NodeInfo& n = skeleton_.nodes[node];
  return n.textureSize > 0 ? n.memoryBytes - n.textureBytes : n.memoryBytes;
}

std::uint64_t CappedResidency::textureBytes(std::uint32_t node) const {
  return textureIndex_[node] == kNoNode ? 0 : skeleton_.nodes[node].textureBytes;
}

std::uint64_t CappedResidency::bytesOf(std::span<const std::uint32_t> nodes) const {
  std::uint64_t total = 0;
  std::unordered_set<std::uint32_t> seen;
  for (std::uint32_t n : nodes) {
    total += meshBytes(n);
    const std::uint32_t t = textureIndex_[n];
    if (t != kNoNode && seen.insert(t).second) total += textureBytes(n);
  }
  return total;
}

void CappedResidency::add(std::uint32_t node) {
  assert(!isResident(node));
  stamp_[node] = now_;
  ++count_;
  bytes_ += meshBytes(node);
  if (const std::uint32_t t = textureIndex_[node]; t != kNoNode && users_[t]++ == 0)
    bytes_ += textureBytes(node);
  peak_ = std::max(peak_, bytes_);
}

void CappedResidency::remove(std::uint32_t node) {
  assert(isResident(node));
  stamp_[node] = 0;
  --count_;
  bytes_ -= meshBytes(node);
  if (const std::uint32_t t = textureIndex_[node]; t != kNoNode && --users_[t] == 0)
    bytes_ -= textureBytes(node);
}

CappedResidency::Change CappedResidency::ensure(std::span<const std::uint32_t> batch) {
  ++now_;
  Change change;
  for (std::uint32_t n : batch) {
    assert(n < stamp_.size());
    if (isResident(n))
      stamp_[n] = now_;
    else
      change.load.push_back(n);
  }
  // What the residency holds once the batch is in, without evicting: its resident nodes, the
  // batch's new ones, and the new ones' textures that no resident node holds.
  std::uint64_t after = bytes_;
  std::unordered_set<std::uint32_t> newTextures, needed;  // needed: the batch's textures
  for (std::uint32_t n : batch)
    if (textureIndex_[n] != kNoNode) needed.insert(textureIndex_[n]);
  for (std::uint32_t n : change.load) {
    after += meshBytes(n);
    const std::uint32_t t = textureIndex_[n];
    if (t != kNoNode && users_[t] == 0 && newTextures.insert(t).second) after += textureBytes(n);
  }
  if (cap_ > 0 && after > cap_) {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> old;  // (stamp, node) outside the batch
    for (std::uint32_t n = 0; n < stamp_.size(); ++n)
      if (stamp_[n] != 0 && stamp_[n] != now_) old.emplace_back(stamp_[n], n);
    std::sort(old.begin(), old.end());
    for (const auto& [stamp, n] : old) {
      if (after <= cap_) break;
      // Its texture goes with the last holder, unless a batch node needs it.
      after -= meshBytes(n);
      const std::uint32_t t = textureIndex_[n];
      remove(n);
      if (t != kNoNode && users_[t] == 0 && !needed.count(t)) after -= textureBytes(n);
      change.evict.push_back(n);
    }
  }
  for (std::uint32_t n : change.load) add(n);
  assert(bytes_ == after);
  return change;
}

void CappedResidency::clear() {
  std::fill(stamp_.begin(), stamp_.end(), 0);
  std::fill(users_.begin(), users_.end(), 0);
  bytes_ = 0;
  count_ = 0;
}

std::vector<std::vector<std::uint32_t>> partitionFront(std::span<const std::uint32_t> front,
                                                       const CappedResidency& residency) {
  std::vector<std::vector<std::uint32_t>> batches;
  if (front.empty()) return batches;
  const std::uint64_t cap = residency.capBytes();
  if (cap == 0) {
    batches.emplace_back(front.begin(), front.end());
    return batches;
  }
  // The resident nodes first; then the others, each texture's nodes together at the place of the
  // first of them (front order otherwise).
  std::vector<std::uint32_t> order;
  for (std::uint32_t n : front)
    if (residency.isResident(n)) order.push_back(n);
  const std::size_t resident = order.size();
  std::unordered_map<std::uint32_t, std::size_t> groupOf;  // texture key -> group
  std::vector<std::vector<std::uint32_t>> groups;
  for (std::uint32_t n : front) {
    if (residency.isResident(n)) continue;
    const std::uint32_t t = residency.textureKey(n);
    if (t == kNoNode) {
      groups.push_back({n});
      continue;
    }
    auto [it, fresh] = groupOf.try_emplace(t, groups.size());
    if (fresh) groups.emplace_back();
    groups[it->second].push_back(n);
  }
  for (const auto& g : groups) order.insert(order.end(), g.begin(), g.end());

  std::vector<std::uint32_t> batch;
  std::unordered_set<std::uint32_t> textures;  // texture keys held by the batch
  std::uint64_t bytes = 0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::uint32_t n = order[i];
    const std::uint32_t t = residency.textureKey(n);
    const bool fresh = t != kNoNode && !textures.count(t);
    const std::uint64_t need = residency.meshBytes(n) + (fresh ? residency.textureBytes(n) : 0);
    // The resident nodes fit together (they are held now); the first other starts a batch.
    if (!batch.empty() && ((i == resident && resident > 0) || bytes + need > cap)) {
      batches.push_back(std::move(batch));
      batch.clear();
      textures.clear();
      bytes = 0;
      i -= 1;  // n again, against the new batch (its texture is then fresh)
      continue;
    }
    batch.push_back(n);
    bytes += need;
    if (fresh) textures.insert(t);
  }
  if (!batch.empty()) batches.push_back(std::move(batch));
  return batches;
}

}  // namespace hlod::study
