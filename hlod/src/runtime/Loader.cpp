// Lakhia III-D loading thread. See hlod/runtime/Loader.h for the contract. Its parts live in
// runtime/loader/: this file runs them, on the loader's thread or step by step.
#include "hlod/runtime/Loader.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <unordered_set>

#include "runtime/loader/Eviction.h"
#include "runtime/loader/LinkEmulator.h"
#include "runtime/loader/LoadSchedule.h"
#include "runtime/loader/NodeMemory.h"
#include "runtime/loader/PartialBuffers.h"
#include "runtime/loader/SharedTextures.h"

namespace hlod {

Loader::Loader(const NodeSource& source, LoaderParams params)
    : source_(source),
      skeleton_(source.skeleton()),
      params_(params),
      memory_(std::make_unique<NodeMemory>(source.skeleton(), params.textures)),
      link_(std::make_unique<LinkEmulator>(params.ioMbps, params.ioLatencyMs, params.ioRequests,
                                           params.clock)),
      textures_(std::make_unique<SharedTextures>()),
      partials_(std::make_unique<PartialBuffers>()),
      schedule_(std::make_unique<LoadSchedule>()),
      residentFlag_(new std::atomic<bool>[source.skeleton().nodes.size()]),
      resident_(source.skeleton().nodes.size()),
      isRoot_(source.skeleton().nodes.size(), 0),
      failed_(source.skeleton().nodes.size(), 0) {
  for (std::size_t i = 0; i < resident_.size(); ++i) residentFlag_[i].store(false);
  EvictionLimits limits{params_.capBytes, params_.c_memory, params_.maxMemory, 0};
  for (std::uint32_t r : skeleton_.roots) {
    if (r < isRoot_.size() && !isRoot_[r]) {
      isRoot_[r] = 1;
      limits.rootBytes += memory_->memory(r);
    }
  }
  eviction_ = std::make_unique<Eviction>(skeleton_, *memory_, *textures_, *partials_, *schedule_,
                                         resident_, isRoot_, limits);
  if (params_.chunkBytes == 0) params_.chunkBytes = 64 * 1024;
  counters_.capBytes = params_.capBytes;
}

std::uint64_t Loader::holdTextureLocked(std::uint32_t node,
                                        const std::shared_ptr<const Image>& image) {
  const NodeInfo& n = skeleton_.nodes[node];
  return textures_->hold(n.textureOffset, image) ? n.textureBytes : 0;
}

void Loader::releaseTextureLocked(std::uint32_t node) {
  const NodeInfo& n = skeleton_.nodes[node];
  if (textures_->release(n.textureOffset)) counters_.residentBytes -= n.textureBytes;
}

template <class Loadable>
void Loader::issueAheadLocked(std::uint32_t chosen, Loadable&& loadable) {
  if (!link_->hasLatency()) return;
  const std::size_t window = link_->window();
  std::vector<std::uint32_t> ahead;  // in priority order
  std::unordered_set<std::uint32_t> taken;
  // Returns false once the window is full: the scans stop there, not at the end of the list.
  auto consider = [&](std::uint32_t n) {
    if (ahead.size() >= window) return false;
    if (n == chosen || taken.count(n) || !loadable(n)) return true;
    taken.insert(n);
    ahead.push_back(n);
    return true;
  };
  if (chosen < resident_.size() && isRoot_[chosen]) {
    for (std::uint32_t r : skeleton_.roots)
      if (!consider(r)) break;
  } else {
    for (const auto& [p, n] : schedule_->order())
      if (!consider(n)) break;
  }
  link_->requestAhead(chosen, ahead);
}

Loader::~Loader() {
  stop();
}

Status Loader::loadRoots() {
  std::lock_guard stepLock(stepMutex_);
  // hlod_0 is loaded before the first frame: on an emulated link too slow for it, say so now
  // instead of waiting for hours without a word.
  if (link_->throttled()) {
    std::uint64_t bytes = 0;
    for (std::uint32_t r : skeleton_.roots)
      if (r < skeleton_.nodes.size()) bytes += memory_->readSize(r);
    const double seconds = link_->seconds(bytes, skeleton_.roots.size());
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
    const std::uint64_t size = memory_->readSize(r);
    if (params_.cache && !params_.cache->reserve(memory_->memory(r)))
      return makeError("hlod_0 node " + std::to_string(r) +
                       " does not fit the server's node memory cap");
    std::vector<std::byte> bytes;
    try {
      bytes.resize(size);
    } catch (const std::bad_alloc&) {
      if (params_.cache) params_.cache->release(memory_->memory(r));
      return makeError("hlod_0 node " + std::to_string(r) + ": cannot allocate " +
                       std::to_string(size) + " bytes");
    }
    for (std::uint64_t off = 0; off < size; off += params_.chunkBytes) {
      const std::size_t len =
          static_cast<std::size_t>(std::min<std::uint64_t>(params_.chunkBytes, size - off));
      throttle(r, off, len);
      Status s = source_.readPayloadChunk(r, off, std::span<std::byte>(bytes.data() + off, len));
      if (!s) {
        if (params_.cache) params_.cache->release(memory_->memory(r));
        return makeError("hlod_0 node " + std::to_string(r) + ": " + s.message());
      }
      if (stopRequested()) return makeError("stopped while loading hlod_0");
    }
    Result<LocalMesh> mesh = decodeGuarded(r, bytes);
    if (!mesh) {
      if (params_.cache) params_.cache->release(memory_->memory(r));
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
      workCv_.wait_for(lock, std::chrono::milliseconds(50),
                       [&] { return stop_ || schedule_->dirty(); });
    }
  }
}

void Loader::setWanted(std::span<const LoadRequest> requests) {
  std::lock_guard lock(mutex_);
  schedule_->setWanted(requests, resident_.size());
  idle_ = false;
  workCv_.notify_one();
}

void Loader::prefetch(std::span<const LoadRequest> requests) {
  std::lock_guard lock(mutex_);
  schedule_->setPrefetch(requests, resident_.size());
  idle_ = false;
  workCv_.notify_one();
}

void Loader::dropPartialLocked(std::uint32_t node) {
  const std::unique_ptr<PartialLoad> part = partials_->take(node);
  if (!part) return;
  counters_.inFlightBytes -= part->reserved;
  if (part->cacheReserved) params_.cache->release(memory_->memory(node));
  if (part->textureHeld) releaseTextureLocked(node);
  if (current_ == node) current_ = kNoNode;
}

void Loader::unloadLocked(std::uint32_t node) {
  const NodeInfo& n = skeleton_.nodes[node];
  resident_[node].reset();
  residentFlag_[node].store(false);
  counters_.residentBytes -=
      memory_->hasTexture(node) ? n.memoryBytes - n.textureBytes : memory_->memory(node);
  if (memory_->hasTexture(node)) releaseTextureLocked(node);
  counters_.residentCost -= n.cost;
  --counters_.residentNodes;
  ++counters_.unloads;
  events_.push_back({LoaderEvent::Kind::Unloaded, node, nullptr});
  schedule_->markDirty();
}

bool Loader::makeRoomLocked(std::uint32_t node, double priority) {
  std::vector<EvictionVictim> victims;
  if (!eviction_->makeRoom(
          node, priority,
          {counters_.residentBytes + counters_.inFlightBytes, counters_.residentCost}, victims))
    return false;
  // In the order taken: children before their parents.
  for (const EvictionVictim& v : victims) {
    if (v.resident) {
      unloadLocked(v.node);
    } else {
      dropPartialLocked(v.node);
    }
  }
  return true;
}

std::uint32_t Loader::chooseLocked() {
  // Loadable now: not resident, not failed, its parent resident; and it fits in memory
  // (partial buffers have theirs reserved already).
  auto loadable = [&](std::uint32_t n) {
    if (resident_[n] || failed_[n]) return false;
    const std::uint32_t parent = skeleton_.nodes[n].parent;
    return parent == kNoNode || (parent < resident_.size() && resident_[parent]);
  };
  const std::uint32_t chosen = schedule_->choose(
      skeleton_, lastFinished_, params_.c_siblingRatio,
      [&](std::uint32_t n) { return !resident_[n] && !failed_[n]; }, loadable,
      [&](std::uint32_t n, double p) { return partials_->contains(n) || makeRoomLocked(n, p); },
      [&](std::uint32_t n) { return eviction_->neverFits(n); });
  if (chosen != kNoNode)
    issueAheadLocked(chosen, loadable);
  else
    link_->cancelAhead();  // idle: nothing stays requested
  return chosen;
}

void Loader::throttle(std::uint32_t node, std::uint64_t offset, std::size_t len) {
  // Called with stepMutex_ held: the link's stream position is the step's state.
  const bool continues = link_->continues(skeleton_.nodes[node].payloadOffset + offset, len);
  double ms = 0.0;
  if (!continues) {
    // A new request: its latency, less what has passed since it was requested ahead.
    const LinkClock::TimePoint now = link_->clock().now();
    std::lock_guard lock(mutex_);
    ++counters_.requests;
    ms = link_->latencyMs(node, now);
    counters_.latencyMs += ms;
  }
  ms += link_->transferMs(len);
  if (ms > 0.0) {
    // Not a plain sleep: a stop() must not wait out an emulated transfer of minutes.
    std::unique_lock lock(mutex_);
    link_->clock().waitFor(lock, workCv_, LinkClock::Milliseconds(ms), [&] { return stop_; });
  }
}

bool Loader::step() {
  std::lock_guard stepLock(stepMutex_);
  std::uint32_t node;
  PartialLoad* part;
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
    part = partials_->find(node);
    if (!part && params_.cache) {
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
    if (!part) {
      auto fresh = std::make_unique<PartialLoad>();
      // A texture held already (shared with a resident node) is neither read nor counted again.
      fresh->textureHeld = memory_->textureHeld(node, *textures_);
      const std::uint64_t readSize =
          fresh->textureHeld ? skeleton_.nodes[node].meshSize() : memory_->readSize(node);
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
        if (!params_.cache->reserve(memory_->memory(node))) {
          // The sessions of this store hold the server's cap: wait for them to let go.
          current_ = kNoNode;
          idle_ = true;
          progressCv_.notify_all();
          return false;
        }
        fresh->cacheReserved = true;
      }
      // Reserve what the node will hold decoded, so that finishing it cannot pass the cap.
      fresh->reserved = memory_->charge(node, *textures_);
      if (fresh->textureHeld) holdTextureLocked(node, nullptr);
      part = &partials_->add(node, std::move(fresh));
      counters_.inFlightBytes += part->reserved;
      counters_.peakBytes =
          std::max(counters_.peakBytes, counters_.residentBytes + counters_.inFlightBytes);
      ++counters_.loadsStarted;
      // Too many kept buffers: drop the least important other one.
      while (partials_->size() > std::max<std::size_t>(1, params_.maxPartials)) {
        dropPartialLocked(partials_->leastImportantOther(
            node, [&](std::uint32_t n) { return schedule_->priorityOf(n); }));
      }
    }
    size = part->bytes.size();
    offset = part->filled;
    len = static_cast<std::size_t>(std::min<std::uint64_t>(params_.chunkBytes, size - offset));
  }
  // Only step() adds or removes partial buffers, and steps are serialised: `part` stays valid
  // unlocked.
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
    return makeError("cannot allocate the decoded payload (" +
                     std::to_string(memory_->memory(node)) + " bytes)");
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
  schedule_->markDirty();
  progressCv_.notify_all();
}

void Loader::finishLocked(std::uint32_t node, Result<LocalMesh> mesh) {
  // The cache takes over the reservation of a decoded node; a failed one gives it back.
  PartialLoad* const part = partials_->find(node);
  if (part && part->cacheReserved && mesh) part->cacheReserved = false;
  // A shared texture held already replaces the node's own copy (or stands in for the texture
  // section it did not read); it stays held from here until the node holds it itself.
  const bool pin = mesh && memory_->hasTexture(node);
  if (pin) {
    if (const std::uint64_t offset = skeleton_.nodes[node].textureOffset; textures_->held(offset))
      mesh->texture = textures_->image(offset);
    counters_.residentBytes += holdTextureLocked(node, mesh->texture);
  }
  dropPartialLocked(node);
  if (current_ == node) current_ = kNoNode;
  schedule_->markDirty();
  if (!mesh) {
    failLocked(node, mesh.message());
    return;
  }
  // (hlod_0 nodes from loadRoots have no partial: they reserved in the cache themselves.)
  const std::uint64_t bytes = memory_->memory(node);
  adoptLocked(node, params_.cache ? params_.cache->insert(NodeCache::key(params_.cacheStore, node),
                                                          std::move(mesh).value(), bytes)
                                  : std::make_shared<const LocalMesh>(std::move(mesh).value()));
  if (pin) releaseTextureLocked(node);
}

void Loader::adoptLocked(std::uint32_t node, std::shared_ptr<const LocalMesh> shared) {
  schedule_->markDirty();
  const NodeInfo& n = skeleton_.nodes[node];
  resident_[node] = shared;
  residentFlag_[node].store(true);
  counters_.residentBytes +=
      memory_->hasTexture(node)
          ? n.memoryBytes - n.textureBytes + holdTextureLocked(node, shared->texture)
          : memory_->memory(node);
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
