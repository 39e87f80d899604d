// Eviction: what to unload to make room for a node (runtime/loader/Eviction.h).
#include "runtime/loader/Eviction.h"

#include <algorithm>
#include <cassert>
#include <unordered_map>
#include <utility>

namespace hlod {

Eviction::Eviction(const Skeleton& skeleton, const NodeMemory& memory,
                   const SharedTextures& textures, const PartialBuffers& partials,
                   const LoadSchedule& schedule,
                   const std::vector<std::shared_ptr<const LocalMesh>>& resident,
                   const std::vector<std::uint8_t>& isRoot, const EvictionLimits& limits)
    : skeleton_(skeleton),
      memory_(memory),
      textures_(textures),
      partials_(partials),
      schedule_(schedule),
      resident_(resident),
      isRoot_(isRoot),
      limits_(limits) {}

bool Eviction::neverFits(std::uint32_t node) const {
  // hlod_0 is never unloaded: a node larger than what it leaves of the cap can never load.
  const std::uint64_t cap = limits_.capBytes;
  const std::uint64_t rootBytes = limits_.rootBytes;
  return cap > 0 && (rootBytes >= cap || memory_.memory(node) > cap - rootBytes);
}

bool Eviction::hasResidentChild(std::uint32_t node) const {
  const NodeInfo& n = skeleton_.nodes[node];
  assert(n.childCount == 0 || n.firstChild + std::size_t(n.childCount) <= resident_.size());
  for (std::uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c) {
    if (resident_[c]) return true;
  }
  return false;
}

bool Eviction::makeRoom(std::uint32_t node, double priority, const MemoryInUse& inUse,
                        std::vector<EvictionVictim>& victims) {
  victims.clear();
  const NodeInfo& info = skeleton_.nodes[node];
  const bool capOn = limits_.capBytes > 0;
  const bool costOn = limits_.c_memory > 0.0;
  // Once decoded the node holds memoryBytes (more than its compressed read buffer).
  std::uint64_t bytes = inUse.bytes + memory_.charge(node, textures_);
  double cost = inUse.cost + info.cost;
  auto fits = [&] {
    return (!capOn || bytes <= limits_.capBytes) &&
           (!costOn || limits_.c_memory * cost < limits_.maxMemory);
  };
  if (fits()) return true;
  if (neverFits(node)) return false;

  // Victims less important than the node: kept partial buffers first (cheap to drop), then
  // resident nodes without resident children, lowest priority first, deeper levels first.
  using Victim = EvictionVictim;
  auto better = [](const Victim& a, const Victim& b) {
    if (a.resident != b.resident) return !a.resident;
    if (a.priority != b.priority) return a.priority < b.priority;
    if (a.level != b.level) return a.level > b.level;
    return a.node < b.node;
  };
  // A max-heap of the best victim: std::push_heap keeps the largest by `less` on top.
  auto less = [&](const Victim& a, const Victim& b) { return better(b, a); };
  std::vector<Victim> heap;
  auto offer = [&](const Victim& v) {
    heap.push_back(v);
    std::push_heap(heap.begin(), heap.end(), less);
  };
  for (const auto& [n, part] : partials_) {
    const double p = schedule_.priorityOf(n);
    if (n != node && p < priority) offer({false, p, skeleton_.nodes[n].level, n});
  }
  // Never a victim: what the node's own drawing depends on, its ancestors and their siblings
  // (the selectors draw a node only through its resident parent, and replace a parent by its
  // visible children only when all of them are resident). Evicting an ancestor's sibling broke
  // that group, so the node's subtree dropped out of the wanted set (priority -1) until the
  // sibling, reloaded in place of that subtree, made the group whole again, the subtree came
  // back and evicted the sibling again: under a still camera, forever.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> dependsOn;  // [first, end) node ranges
  for (std::uint32_t a = info.parent; a != kNoNode; a = skeleton_.nodes[a].parent) {
    const std::uint32_t up = skeleton_.nodes[a].parent;
    if (up != kNoNode)
      dependsOn.emplace_back(skeleton_.nodes[up].firstChild,
                             skeleton_.nodes[up].firstChild + skeleton_.nodes[up].childCount);
    else
      dependsOn.emplace_back(a, a + 1);
  }
  auto evictable = [&](std::uint32_t n) {
    if (isRoot_[n]) return false;
    for (const auto& [first, end] : dependsOn)
      if (n >= first && n < end) return false;
    return true;
  };
  // What a resident node is worth: its own priority, or that of the most important wanted node
  // below its siblings, which are drawn only while its group is whole. Valued alone, a group's
  // member went for a slightly more important node elsewhere; the group's subtrees, no longer
  // visited, dropped to -1 and went wholesale; the member came back in their place, the subtrees
  // after it, taking another group's member: round and round under a still camera.
  // below_[n]: the highest wanted priority in n's resident subtree, n excluded (children follow
  // their parents in the skeleton, so one pass from the end fills it).
  below_.assign(resident_.size(), -1.0);
  for (std::size_t i = resident_.size(); i-- > 0;) {
    if (!resident_[i]) continue;
    const std::uint32_t q = skeleton_.nodes[i].parent;
    if (q != kNoNode) below_[q] = std::max(below_[q], std::max(below_[i], schedule_.priorityOf(i)));
  }
  auto worth = [&](std::uint32_t n) {
    double p = schedule_.priorityOf(n);
    const std::uint32_t q = skeleton_.nodes[n].parent;
    if (q == kNoNode) return p;
    const NodeInfo& qn = skeleton_.nodes[q];
    for (std::uint32_t c = qn.firstChild; c < qn.firstChild + qn.childCount; ++c)
      if (c != n && resident_[c]) p = std::max(p, below_[c]);
    return p;
  };
  // A node holding the texture the node will share stays: the node's charge counts on it.
  const bool shares = memory_.textureHeld(node, textures_);
  auto sharesTexture = [&](std::uint32_t n) {
    return shares && memory_.hasTexture(n) &&
           skeleton_.nodes[n].textureOffset == info.textureOffset;
  };
  for (std::uint32_t n = 0; n < resident_.size(); ++n) {
    if (!resident_[n] || !evictable(n) || hasResidentChild(n) || sharesTexture(n)) continue;
    const double p = worth(n);
    if (p < priority) offer({true, p, skeleton_.nodes[n].level, n});
  }
  // Dry run first: evict nothing unless the node then fits. A parent whose last resident child
  // the dry run takes becomes a victim too, so that a chain of nodes the camera has left can go
  // whole: taking only the nodes without resident children, a node larger than those never
  // loaded while the cache stayed full of unwanted ancestors.
  std::unordered_map<std::uint32_t, std::uint32_t> childrenLeft;
  std::unordered_map<std::uint64_t, std::uint32_t> texturesLeft;  // holders the dry run leaves
  while (!fits() && !heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), less);
    const Victim v = heap.back();
    heap.pop_back();
    victims.push_back(v);
    const NodeInfo& vn = skeleton_.nodes[v.node];
    // What evicting it frees: its reservation, or its decoded mesh and, once the dry run has
    // taken every holder of its texture, that texture.
    if (!v.resident) {
      bytes -= partials_.find(v.node)->reserved;
      continue;
    }
    if (memory_.hasTexture(v.node)) {
      bytes -= vn.memoryBytes - vn.textureBytes;
      auto [left, fresh] = texturesLeft.try_emplace(vn.textureOffset, 0u);
      if (fresh) left->second = textures_.users(vn.textureOffset);
      if (--left->second == 0) bytes -= vn.textureBytes;
    } else {
      bytes -= memory_.memory(v.node);
    }
    cost -= vn.cost;
    const std::uint32_t q = vn.parent;
    if (q == kNoNode || !evictable(q)) continue;
    auto [left, fresh] = childrenLeft.try_emplace(q, 0u);
    if (fresh) {
      const NodeInfo& qn = skeleton_.nodes[q];
      for (std::uint32_t c = qn.firstChild; c < qn.firstChild + qn.childCount; ++c)
        left->second += resident_[c] ? 1u : 0u;
    }
    if (--left->second == 0 && !sharesTexture(q)) {
      const double p = worth(q);
      if (p < priority) offer({true, p, skeleton_.nodes[q].level, q});
    }
  }
  if (!fits()) {
    victims.clear();
    return false;
  }
  return true;
}

}  // namespace hlod
