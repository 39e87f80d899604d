// Lakhia III-D loading thread. See hlod/runtime/Loader.h for the contract.
#include "hlod/runtime/Loader.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>

namespace hlod {

Loader::Loader(const NodeSource& source, LoaderParams params)
    : source_(source),
      skeleton_(source.skeleton()),
      params_(params),
      residentFlag_(new std::atomic<bool>[source.skeleton().nodes.size()]),
      resident_(source.skeleton().nodes.size()),
      isRoot_(source.skeleton().nodes.size(), 0),
      failed_(source.skeleton().nodes.size(), 0) {
  for (std::size_t i = 0; i < resident_.size(); ++i) residentFlag_[i].store(false);
  for (std::uint32_t r : skeleton_.roots) {
    if (r < isRoot_.size() && !isRoot_[r]) {
      isRoot_[r] = 1;
      rootBytes_ += memoryOf(r);
    }
  }
  if (params_.chunkBytes == 0) params_.chunkBytes = 64 * 1024;
  counters_.capBytes = params_.capBytes;
}

std::uint64_t Loader::readSizeOf(std::uint32_t node) const {
  const NodeInfo& n = skeleton_.nodes[node];
  return params_.textures ? n.payloadSize : n.payloadSize - n.textureSize;
}

std::uint64_t Loader::memoryOf(std::uint32_t node) const {
  const NodeInfo& n = skeleton_.nodes[node];
  return params_.textures ? n.memoryBytes : n.memoryBytes - n.textureBytes;
}

bool Loader::hasTexture(std::uint32_t node) const {
  return params_.textures && skeleton_.nodes[node].textureSize > 0;
}

bool Loader::textureHeldLocked(std::uint32_t node) const {
  return hasTexture(node) && textures_.count(skeleton_.nodes[node].textureOffset) > 0;
}

std::uint64_t Loader::chargeLocked(std::uint32_t node) const {
  const NodeInfo& n = skeleton_.nodes[node];
  return textureHeldLocked(node) ? n.memoryBytes - n.textureBytes : memoryOf(node);
}

std::uint64_t Loader::holdTextureLocked(std::uint32_t node,
                                        const std::shared_ptr<const Image>& image) {
  const NodeInfo& n = skeleton_.nodes[node];
  auto [it, fresh] = textures_.try_emplace(n.textureOffset);
  if (fresh) it->second.image = image;
  ++it->second.users;
  return fresh ? n.textureBytes : 0;
}

void Loader::releaseTextureLocked(std::uint32_t node) {
  const NodeInfo& n = skeleton_.nodes[node];
  auto it = textures_.find(n.textureOffset);
  assert(it != textures_.end() && it->second.users > 0);
  if (--it->second.users > 0) return;
  textures_.erase(it);
  counters_.residentBytes -= n.textureBytes;
}

template <class Loadable>
void Loader::issueAheadLocked(std::uint32_t chosen, Loadable&& loadable) {
  if (!(params_.ioLatencyMs > 0.0)) return;
  const auto now = std::chrono::steady_clock::now();
  const std::size_t ahead = std::max<std::size_t>(1, params_.ioRequests) - 1;
  std::unordered_map<std::uint32_t, std::chrono::steady_clock::time_point> kept;
  // Returns false once the window is full: the scans stop there, not at the end of the list.
  auto consider = [&](std::uint32_t n) {
    if (kept.size() >= ahead) return false;
    if (n == chosen || kept.count(n) || !loadable(n)) return true;
    auto it = issued_.find(n);
    kept.emplace(n, it != issued_.end() ? it->second : now);
    return true;
  };
  if (chosen < resident_.size() && isRoot_[chosen]) {
    for (std::uint32_t r : skeleton_.roots)
      if (!consider(r)) break;
  } else {
    for (const auto& [p, n] : order_)
      if (!consider(n)) break;
  }
  // The chosen node keeps its issue time until throttle() consumes it; the rest not in the
  // window is cancelled.
  if (auto it = issued_.find(chosen); it != issued_.end()) kept.insert(*it);
  issued_.swap(kept);
}

Loader::~Loader() {
  stop();
}

Status Loader::loadRoots() {
  std::lock_guard stepLock(stepMutex_);
  // hlod_0 is loaded before the first frame: on an emulated link too slow for it, say so now
  // instead of waiting for hours without a word.
  if (params_.ioMbps > 0.0) {
    std::uint64_t bytes = 0;
    for (std::uint32_t r : skeleton_.roots)
      if (r < skeleton_.nodes.size()) bytes += readSizeOf(r);
    const double seconds = static_cast<double>(bytes) * 8.0 / (params_.ioMbps * 1e6) +
                           params_.ioLatencyMs * 1e-3 * static_cast<double>(skeleton_.roots.size());
    if (seconds > kMaxRootLoadSeconds) {
      char msg[256];
      std::snprintf(msg, sizeof msg,
                    "loading hlod_0 (%.1f MB) over the emulated link of %g Mbit/s would take "
                    "%.0f s before the first frame (more than %.0f s): use a faster link",
                    static_cast<double>(bytes) / 1e6, params_.ioMbps, seconds, kMaxRootLoadSeconds);
      return makeError(msg);
    }
  }
  for (std::uint32_t r : skeleton_.roots) {
    if (r >= resident_.size())
      return makeError("hlod_0 node " + std::to_string(r) + " out of range");
    if (residentFlag_[r].load()) continue;
    if (params_.cache) {
      if (auto hit = params_.cache->find(NodeCache::key(params_.cacheStore, r))) {
        std::lock_guard lock(mutex_);
        ++counters_.loadsStarted;
        ++counters_.cacheHits;
        adoptLocked(r, std::move(hit));
        continue;
      }
    }
    {
      // The next roots are requested while this one streams, as in the loading thread.
      std::lock_guard lock(mutex_);
      issueAheadLocked(r, [&](std::uint32_t n) { return isRoot_[n] && !resident_[n]; });
    }
    const std::uint64_t size = readSizeOf(r);
    if (params_.cache && !params_.cache->reserve(memoryOf(r)))
      return makeError("hlod_0 node " + std::to_string(r) +
                       " does not fit the server's node memory cap");
    std::vector<std::byte> bytes;
    try {
      bytes.resize(size);
    } catch (const std::bad_alloc&) {
      if (params_.cache) params_.cache->release(memoryOf(r));
      return makeError("hlod_0 node " + std::to_string(r) + ": cannot allocate " +
                       std::to_string(size) + " bytes");
    }
    for (std::uint64_t off = 0; off < size; off += params_.chunkBytes) {
      const std::size_t len =
          static_cast<std::size_t>(std::min<std::uint64_t>(params_.chunkBytes, size - off));
      throttle(r, off, len);
      Status s = source_.readPayloadChunk(r, off, std::span<std::byte>(bytes.data() + off, len));
      if (!s) {
        if (params_.cache) params_.cache->release(memoryOf(r));
        return makeError("hlod_0 node " + std::to_string(r) + ": " + s.message());
      }
      if (stopRequested()) return makeError("stopped while loading hlod_0");
    }
    Result<LocalMesh> mesh = decodeGuarded(r, bytes);
    if (!mesh) {
      if (params_.cache) params_.cache->release(memoryOf(r));
      return makeError("hlod_0 node " + std::to_string(r) + ": " + mesh.message());
    }
    std::lock_guard lock(mutex_);
    ++counters_.loadsStarted;
    counters_.bytesRead += size;
    finishLocked(r, std::move(mesh));
  }
  std::lock_guard lock(mutex_);
  counters_.rootsExceedCap = params_.capBytes > 0 && counters_.residentBytes > params_.capBytes;
  return Ok{};
}

void Loader::start() {
  if (thread_.joinable()) return;
  {
    std::lock_guard lock(mutex_);
    stop_ = false;
  }
  thread_ = std::thread([this] { run(); });
}

void Loader::stop() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  workCv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void Loader::run() {
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (stop_) return;
    }
    if (!step()) {
      std::unique_lock lock(mutex_);
      workCv_.wait_for(lock, std::chrono::milliseconds(50), [&] { return stop_ || orderDirty_; });
    }
  }
}

void Loader::setWanted(std::span<const LoadRequest> requests) {
  std::lock_guard lock(mutex_);
  wanted_.clear();
  for (const LoadRequest& r : requests) {
    if (r.node >= resident_.size() || !std::isfinite(r.priority)) continue;
    auto [it, inserted] = wanted_.try_emplace(r.node, r.priority);
    if (!inserted) it->second = std::max(it->second, r.priority);
  }
  orderDirty_ = true;
  idle_ = false;
  workCv_.notify_one();
}

void Loader::prefetch(std::span<const LoadRequest> requests) {
  std::lock_guard lock(mutex_);
  prefetch_.clear();
  for (const LoadRequest& r : requests) {
    if (r.node >= resident_.size() || !std::isfinite(r.priority)) continue;
    auto [it, inserted] = prefetch_.try_emplace(r.node, r.priority);
    if (!inserted) it->second = std::max(it->second, r.priority);
  }
  orderDirty_ = true;
  idle_ = false;
  workCv_.notify_one();
}

double Loader::priorityOf(std::uint32_t node) const {
  double p = -1.0;
  if (auto it = wanted_.find(node); it != wanted_.end()) p = std::max(p, it->second);
  if (auto it = prefetch_.find(node); it != prefetch_.end()) p = std::max(p, it->second);
  return p;
}

bool Loader::hasResidentChildLocked(std::uint32_t node) const {
  const NodeInfo& n = skeleton_.nodes[node];
  assert(n.childCount == 0 || n.firstChild + std::size_t(n.childCount) <= resident_.size());
  for (std::uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c) {
    if (resident_[c]) return true;
  }
  return false;
}

void Loader::dropPartialLocked(std::uint32_t node) {
  auto it = partials_.find(node);
  if (it == partials_.end()) return;
  counters_.inFlightBytes -= it->second->reserved;
  if (it->second->cacheReserved) params_.cache->release(memoryOf(node));
  if (it->second->textureHeld) releaseTextureLocked(node);
  partials_.erase(it);
  if (current_ == node) current_ = kNoNode;
}

void Loader::unloadLocked(std::uint32_t node) {
  const NodeInfo& n = skeleton_.nodes[node];
  resident_[node].reset();
  residentFlag_[node].store(false);
  counters_.residentBytes -= hasTexture(node) ? n.memoryBytes - n.textureBytes : memoryOf(node);
  if (hasTexture(node)) releaseTextureLocked(node);
  counters_.residentCost -= n.cost;
  --counters_.residentNodes;
  ++counters_.unloads;
  events_.push_back({LoaderEvent::Kind::Unloaded, node, nullptr});
  orderDirty_ = true;
}

bool Loader::makeRoomLocked(std::uint32_t node, double priority) {
  const NodeInfo& info = skeleton_.nodes[node];
  const bool capOn = params_.capBytes > 0;
  const bool costOn = params_.c_memory > 0.0;
  // Once decoded the node holds memoryBytes (more than its compressed read buffer).
  std::uint64_t bytes = counters_.residentBytes + counters_.inFlightBytes + chargeLocked(node);
  double cost = counters_.residentCost + info.cost;
  auto fits = [&] {
    return (!capOn || bytes <= params_.capBytes) &&
           (!costOn || params_.c_memory * cost < params_.maxMemory);
  };
  if (fits()) return true;
  if (neverFits(node)) return false;

  // Victims less important than the node: kept partial buffers first (cheap to drop), then
  // resident nodes without resident children, lowest priority first, deeper levels first.
  struct Victim {
    bool resident;
    double priority;
    std::uint32_t level;
    std::uint32_t node;
  };
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
    const double p = priorityOf(n);
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
    if (q != kNoNode) below_[q] = std::max(below_[q], std::max(below_[i], priorityOf(i)));
  }
  auto worth = [&](std::uint32_t n) {
    double p = priorityOf(n);
    const std::uint32_t q = skeleton_.nodes[n].parent;
    if (q == kNoNode) return p;
    const NodeInfo& qn = skeleton_.nodes[q];
    for (std::uint32_t c = qn.firstChild; c < qn.firstChild + qn.childCount; ++c)
      if (c != n && resident_[c]) p = std::max(p, below_[c]);
    return p;
  };
  // A node holding the texture the node will share stays: the node's charge counts on it.
  const bool shares = textureHeldLocked(node);
  auto sharesTexture = [&](std::uint32_t n) {
    return shares && hasTexture(n) && skeleton_.nodes[n].textureOffset == info.textureOffset;
  };
  for (std::uint32_t n = 0; n < resident_.size(); ++n) {
    if (!resident_[n] || !evictable(n) || hasResidentChildLocked(n) || sharesTexture(n)) continue;
    const double p = worth(n);
    if (p < priority) offer({true, p, skeleton_.nodes[n].level, n});
  }
  // Dry run first: evict nothing unless the node then fits. A parent whose last resident child
  // the dry run takes becomes a victim too, so that a chain of nodes the camera has left can go
  // whole: taking only the nodes without resident children, a node larger than those never
  // loaded while the cache stayed full of unwanted ancestors.
  std::unordered_map<std::uint32_t, std::uint32_t> childrenLeft;
  std::unordered_map<std::uint64_t, std::uint32_t> texturesLeft;  // holders the dry run leaves
  std::vector<Victim> taken;
  while (!fits() && !heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), less);
    const Victim v = heap.back();
    heap.pop_back();
    taken.push_back(v);
    const NodeInfo& vn = skeleton_.nodes[v.node];
    // What evicting it frees: its reservation, or its decoded mesh and, once the dry run has
    // taken every holder of its texture, that texture.
    if (!v.resident) {
      bytes -= partials_.at(v.node)->reserved;
      continue;
    }
    if (hasTexture(v.node)) {
      bytes -= vn.memoryBytes - vn.textureBytes;
      auto [left, fresh] = texturesLeft.try_emplace(vn.textureOffset, 0u);
      if (fresh) left->second = textures_.at(vn.textureOffset).users;
      if (--left->second == 0) bytes -= vn.textureBytes;
    } else {
      bytes -= memoryOf(v.node);
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
  if (!fits()) return false;
  // In the order taken: children before their parents.
  for (const Victim& v : taken) {
    if (v.resident) {
      unloadLocked(v.node);
    } else {
      dropPartialLocked(v.node);
    }
  }
  return true;
}

bool Loader::neverFits(std::uint32_t node) const {
  // hlod_0 is never unloaded: a node larger than what it leaves of the cap can never load.
  const std::uint64_t cap = params_.capBytes;
  return cap > 0 && (rootBytes_ >= cap || memoryOf(node) > cap - rootBytes_);
}

std::uint32_t Loader::chooseLocked() {
  if (orderDirty_) {
    order_.clear();
    auto add = [&](const std::unordered_map<std::uint32_t, double>& m) {
      for (const auto& [n, p] : m) {
        if (!resident_[n] && !failed_[n]) order_.push_back({priorityOf(n), n});
      }
    };
    add(wanted_);
    add(prefetch_);
    std::sort(order_.begin(), order_.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    order_.erase(std::unique(order_.begin(), order_.end()), order_.end());
    orderDirty_ = false;
  }
  // A node that does not fit even after evicting everything less important rarely has a
  // lower-priority successor that does (it may evict less): try a few, not the whole list,
  // since each try scans the resident set.
  int roomTries = 4;
  // Loadable now: not resident, not failed, its parent resident; and it fits in memory
  // (partial buffers have theirs reserved already).
  auto loadable = [&](std::uint32_t n) {
    if (resident_[n] || failed_[n]) return false;
    const std::uint32_t parent = skeleton_.nodes[n].parent;
    return parent == kNoNode || (parent < resident_.size() && resident_[parent]);
  };
  auto fits = [&](std::uint32_t n, double p) { return partials_.count(n) || makeRoomLocked(n, p); };
  // The next sibling of the node loaded last, stored right after it: it continues the read, and
  // its group switches only once all of it is resident.
  const std::uint32_t next = lastFinished_ == kNoNode ? kNoNode : lastFinished_ + 1;
  std::uint32_t chosen = kNoNode;
  if (next < resident_.size() && skeleton_.nodes[next].parent != kNoNode &&
      skeleton_.nodes[next].parent == skeleton_.nodes[lastFinished_].parent && loadable(next)) {
    const double p = priorityOf(next);
    const double best = order_.empty() ? 0.0 : order_.front().first;
    if (p >= 0.0 && p >= params_.c_siblingRatio * best && fits(next, p)) chosen = next;
  }
  for (auto it = order_.begin(); chosen == kNoNode && it != order_.end(); ++it) {
    // A node that can never fit costs no try: four of them at the top of the list would
    // otherwise stop every node behind them, however small, for as long as they are wanted.
    if (!loadable(it->second) || neverFits(it->second)) continue;
    if (fits(it->second, it->first))
      chosen = it->second;
    else if (--roomTries == 0)
      break;
  }
  if (chosen != kNoNode)
    issueAheadLocked(chosen, loadable);
  else
    issued_.clear();  // idle: nothing stays requested
  return chosen;
}

void Loader::throttle(std::uint32_t node, std::uint64_t offset, std::size_t len) {
  // Called with stepMutex_ held: streamEnd_ is the step's state.
  const std::uint64_t at = skeleton_.nodes[node].payloadOffset + offset;
  const bool continues = at == streamEnd_;
  streamEnd_ = at + len;
  double ms = 0.0;
  if (!continues) {
    // A new request: its latency, less what has passed since it was requested ahead.
    const auto now = std::chrono::steady_clock::now();
    std::lock_guard lock(mutex_);
    ++counters_.requests;
    ms = std::max(0.0, params_.ioLatencyMs);
    if (auto it = issued_.find(node); it != issued_.end()) {
      ms = std::max(0.0, ms - std::chrono::duration<double, std::milli>(now - it->second).count());
      issued_.erase(it);
    }
    counters_.latencyMs += ms;
  }
  if (params_.ioMbps > 0.0) ms += static_cast<double>(len) * 8.0 / (params_.ioMbps * 1e3);
  if (ms > 0.0) {
    // Not a plain sleep: a stop() must not wait out an emulated transfer of minutes.
    std::unique_lock lock(mutex_);
    workCv_.wait_for(lock, std::chrono::duration<double, std::milli>(ms), [&] { return stop_; });
  }
}

bool Loader::step() {
  std::lock_guard stepLock(stepMutex_);
  std::uint32_t node;
  Partial* part;
  std::uint64_t offset, size;
  std::size_t len;
  {
    std::lock_guard lock(mutex_);
    node = chooseLocked();
    if (node == kNoNode) {
      idle_ = true;
      progressCv_.notify_all();
      return false;
    }
    idle_ = false;
    if (current_ != kNoNode && current_ != node) {
      ++counters_.preemptions;
      if (!params_.keepPartial) dropPartialLocked(current_);
    }
    auto it = partials_.find(node);
    if (it == partials_.end() && params_.cache) {
      // Another session of this store has it decoded: no read, no decode.
      if (auto hit = params_.cache->find(NodeCache::key(params_.cacheStore, node))) {
        if (current_ == node) current_ = kNoNode;
        ++counters_.loadsStarted;
        ++counters_.cacheHits;
        adoptLocked(node, std::move(hit));
        return true;
      }
    }
    current_ = node;
    if (it == partials_.end()) {
      auto fresh = std::make_unique<Partial>();
      // A texture held already (shared with a resident node) is neither read nor counted again.
      fresh->textureHeld = textureHeldLocked(node);
      const std::uint64_t readSize =
          fresh->textureHeld ? skeleton_.nodes[node].meshSize() : readSizeOf(node);
      // The error boundary of the loading thread: a node too large to allocate (a forged
      // skeleton) fails alone instead of ending the process.
      try {
        fresh->bytes.resize(readSize);
      } catch (const std::bad_alloc&) {
        current_ = kNoNode;
        failLocked(node, "cannot allocate " + std::to_string(readSize) + " bytes");
        return true;
      }
      if (params_.cache) {
        if (!params_.cache->reserve(memoryOf(node))) {
          // The sessions of this store hold the server's cap: wait for them to let go.
          current_ = kNoNode;
          idle_ = true;
          progressCv_.notify_all();
          return false;
        }
        fresh->cacheReserved = true;
      }
      // Reserve what the node will hold decoded, so that finishing it cannot pass the cap.
      fresh->reserved = chargeLocked(node);
      if (fresh->textureHeld) holdTextureLocked(node, nullptr);
      it = partials_.emplace(node, std::move(fresh)).first;
      counters_.inFlightBytes += it->second->reserved;
      counters_.peakBytes =
          std::max(counters_.peakBytes, counters_.residentBytes + counters_.inFlightBytes);
      ++counters_.loadsStarted;
      // Too many kept buffers: drop the least important other one.
      while (partials_.size() > std::max<std::size_t>(1, params_.maxPartials)) {
        std::uint32_t worst = kNoNode;
        double worstP = 0.0;
        for (const auto& [n, pp] : partials_) {
          if (n == node) continue;
          const double p = priorityOf(n);
          if (worst == kNoNode || p < worstP) {
            worst = n;
            worstP = p;
          }
        }
        dropPartialLocked(worst);
      }
    }
    part = it->second.get();
    size = part->bytes.size();
    offset = part->filled;
    len = static_cast<std::size_t>(std::min<std::uint64_t>(params_.chunkBytes, size - offset));
  }
  // Only step() changes partials_, and steps are serialised: `part` stays valid unlocked.
  if (len > 0) {
    throttle(node, offset, len);
    if (stopRequested()) return false;  // the transfer was cut short: nothing was read
    Status s = source_.readPayloadChunk(node, offset,
                                        std::span<std::byte>(part->bytes.data() + offset, len));
    std::lock_guard lock(mutex_);
    if (!s) {
      finishLocked(node, Result<LocalMesh>(s.error()));
      return true;
    }
    part->filled += len;
    counters_.bytesRead += len;
    if (part->filled < size) return true;
  }
  Result<LocalMesh> mesh = decodeGuarded(node, part->bytes);
  std::lock_guard lock(mutex_);
  finishLocked(node, std::move(mesh));
  return true;
}

Result<LocalMesh> Loader::decodeGuarded(std::uint32_t node, std::span<const std::byte> bytes) {
  try {
    return source_.decodePayload(node, bytes);
  } catch (const std::bad_alloc&) {
    return makeError("cannot allocate the decoded payload (" + std::to_string(memoryOf(node)) +
                     " bytes)");
  }
}

bool Loader::stopRequested() {
  std::lock_guard lock(mutex_);
  return stop_;
}

void Loader::failLocked(std::uint32_t node, const std::string& why) {
  failed_[node] = 1;
  ++counters_.loadErrors;
  lastError_ = "node " + std::to_string(node) + ": " + why;
  orderDirty_ = true;
  progressCv_.notify_all();
}

void Loader::finishLocked(std::uint32_t node, Result<LocalMesh> mesh) {
  // The cache takes over the reservation of a decoded node; a failed one gives it back.
  const auto part = partials_.find(node);
  const bool reserved = part != partials_.end() && part->second->cacheReserved;
  if (reserved && mesh) part->second->cacheReserved = false;
  // A shared texture held already replaces the node's own copy (or stands in for the texture
  // section it did not read); it stays held from here until the node holds it itself.
  const bool pin = mesh && hasTexture(node);
  if (pin) {
    if (auto t = textures_.find(skeleton_.nodes[node].textureOffset); t != textures_.end())
      mesh->texture = t->second.image;
    counters_.residentBytes += holdTextureLocked(node, mesh->texture);
  }
  dropPartialLocked(node);
  if (current_ == node) current_ = kNoNode;
  orderDirty_ = true;
  if (!mesh) {
    failLocked(node, mesh.message());
    return;
  }
  // (hlod_0 nodes from loadRoots have no partial: they reserved in the cache themselves.)
  const std::uint64_t bytes = memoryOf(node);
  adoptLocked(node, params_.cache ? params_.cache->insert(NodeCache::key(params_.cacheStore, node),
                                                          std::move(mesh).value(), bytes)
                                  : std::make_shared<const LocalMesh>(std::move(mesh).value()));
  if (pin) releaseTextureLocked(node);
}

void Loader::adoptLocked(std::uint32_t node, std::shared_ptr<const LocalMesh> shared) {
  orderDirty_ = true;
  const NodeInfo& n = skeleton_.nodes[node];
  resident_[node] = shared;
  residentFlag_[node].store(true);
  counters_.residentBytes +=
      hasTexture(node) ? n.memoryBytes - n.textureBytes + holdTextureLocked(node, shared->texture)
                       : memoryOf(node);
  lastFinished_ = node;
  counters_.residentCost += n.cost;
  ++counters_.residentNodes;
  ++counters_.loadsFinished;
  counters_.peakBytes =
      std::max(counters_.peakBytes, counters_.residentBytes + counters_.inFlightBytes);
  events_.push_back({LoaderEvent::Kind::Loaded, node, std::move(shared)});
  progressCv_.notify_all();
}

bool Loader::isResident(std::uint32_t node) const {
  return node < resident_.size() && residentFlag_[node].load(std::memory_order_acquire);
}

std::shared_ptr<const LocalMesh> Loader::residentPayload(std::uint32_t node) const {
  std::lock_guard lock(mutex_);
  return node < resident_.size() ? resident_[node] : nullptr;
}

std::vector<LoaderEvent> Loader::drainEvents() {
  std::lock_guard lock(mutex_);
  std::vector<LoaderEvent> out;
  out.swap(events_);
  return out;
}

LoaderCounters Loader::counters() const {
  std::lock_guard lock(mutex_);
  return counters_;
}

std::uint32_t Loader::currentLoad() const {
  std::lock_guard lock(mutex_);
  return current_;
}

std::string Loader::lastError() const {
  std::lock_guard lock(mutex_);
  return lastError_;
}

bool Loader::waitUntilResident(std::span<const std::uint32_t> nodes,
                               std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  auto all = [&] {
    return std::all_of(nodes.begin(), nodes.end(), [&](std::uint32_t n) { return isResident(n); });
  };
  if (!running()) {
    while (!all()) {
      if (std::chrono::steady_clock::now() > deadline || !step()) return all();
    }
    return true;
  }
  std::unique_lock lock(mutex_);
  progressCv_.wait_until(lock, deadline, [&] { return all() || idle_; });
  return all();
}

bool Loader::waitUntilIdle(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  if (!running()) {
    while (step()) {
      if (std::chrono::steady_clock::now() > deadline) return false;
    }
    return true;
  }
  std::unique_lock lock(mutex_);
  return progressCv_.wait_until(lock, deadline, [&] { return idle_; });
}

}  // namespace hlod
