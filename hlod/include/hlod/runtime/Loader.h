#pragma once
// The loading thread (Lakhia III-D): fetches the highest-priority non-resident nodes from a
// NodeSource a chunk at a time, so that a load can be pre-empted when priorities change between
// chunks, decodes them, and keeps memory bounded by unloading the lowest-priority nodes.
//
//   maxMemory > c_memory * sum over resident nodes of cost      (the paper's bound, optional)
//   residentBytes + bytes of loads in progress <= capBytes       (a hard cap in decoded bytes)
//
// Eviction: to make room for a node, nodes less important than it are unloaded, those no longer
// wanted first, deeper levels first, never one the node's drawing depends on (its ancestors and
// their siblings: breaking such a group for the node made the two evict each other forever under
// a still camera); a parent whose children all go may go too. A node larger than the cap less
// hlod_0 is never loaded and does not hold up the others.
//
// hlod_0 nodes are loaded synchronously by loadRoots() and never unloaded (they are what the
// renderer falls back to). A node is loaded only when its parent is resident, and unloaded only
// when none of its children are resident, so the resident set stays a tree closed upwards: the
// selectors reach nodes only through resident parents.
//
// Threads: start() runs the work on an own std::thread; without it, step() does one unit of work
// (one chunk read, or the decode that completes a node) on the caller's thread, for
// deterministic tests. The render thread never waits: isResident() is lock-free,
// residentPayload() and drainEvents() take a short lock.
//
// Shared textures: nodes of one level may share one texture section (NodeInfo::textureOffset).
// It is decoded once and every such node gets the same image; a load whose texture is held
// already reads only the mesh section; the texture counts once in residentBytes, while a resident
// node or a load in progress holds it; eviction to make room for a node never takes a node whose
// texture it is about to share.
//
// Pre-emption: when another node becomes the most important between two chunks, the partial
// buffer of the interrupted node is kept (keepPartial, at most maxPartials buffers, their bytes
// count against capBytes) and the load resumes where it stopped if that node comes back; a kept
// buffer is dropped first when memory is needed. keepPartial = false drops it at once.
//
// The parts, each in its file under hlod/src/runtime/loader/: LoadSchedule (priorities and the
// next node), Eviction (what to unload), NodeMemory (a node's bytes), SharedTextures (texture
// reference counts), PartialBuffers (loads in progress) and LinkEmulator (throttle and latency,
// on LoaderParams::clock); Loader.cpp runs them, on its thread or step by step.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "hlod/runtime/LinkClock.h"
#include "hlod/runtime/NodeCache.h"
#include "hlod/runtime/Selector.h"
#include "hlod/store/NodeSource.h"

namespace hlod {

class Eviction;
class LinkEmulator;
class LoadSchedule;
class NodeMemory;
class PartialBuffers;
class SharedTextures;

struct LoaderParams {
  std::size_t chunkBytes = 64 * 1024;  // bytes read per step (the paper's "small portion")
  double c_memory = 0.0;  // memory per unit of cost (bytes); 0 disables the paper's bound
  double maxMemory = std::numeric_limits<double>::infinity();  // bytes, with c_memory
  std::uint64_t capBytes = 0;  // hard cap on resident + in-progress payload bytes; 0 = no cap
  double ioMbps = 0.0;         // emulated link speed, megabits per second; 0 = unthrottled
  // Emulated latency of every request. A read that goes on where the previous one ended in the
  // payload file (the next chunk of a node, or a sibling stored right after it) continues the
  // same request, as a sequential disk read or a streamed range request does.
  double ioLatencyMs = 0.0;
  // The time of the emulated link (ioMbps, ioLatencyMs): null is the steady clock; a test's
  // clock runs the link without sleeping.
  std::shared_ptr<LinkClock> clock;
  // Requests in flight on the emulated link, as an HTTP/2 client or a disk queue keeps them:
  // while one node streams, the next ioRequests - 1 loadable nodes in priority order are
  // already requested, so their latency runs during that transfer (a node that drops out of
  // them is cancelled, and pays its full latency if it comes back). 1: one at a time.
  std::size_t ioRequests = 4;
  // Siblings are switched as a group (a parent stays drawn until all its visible children are
  // resident), so after a node the loader takes its next wanted sibling, stored right after it,
  // unless the best waiting node is more than 1 / c_siblingRatio times as important.
  double c_siblingRatio = 0.25;
  bool keepPartial = true;
  std::size_t maxPartials = 4;
  // Decoded payloads shared with the other sessions of the same store (nullptr: none). A node
  // alive there is taken without a read; a load reserves its decoded bytes under the cache's cap
  // too, and waits while they do not fit.
  std::shared_ptr<NodeCache> cache;
  std::uint32_t cacheStore = 0;  // this store's number in the cache's keys (NodeCache::key)
  // false: the scene declares no textures. Loads read only the payloads' mesh sections (the
  // texture sections are never read, inflated or kept: NodeInfo::textureSize), and the memory
  // cap counts memoryBytes - textureBytes. Give such a loader a cacheStore of its own: its
  // meshes have no texture.
  bool textures = true;
};

struct LoaderEvent {
  enum class Kind { Loaded, Unloaded };
  Kind kind = Kind::Loaded;
  std::uint32_t node = kNoNode;
  std::shared_ptr<const LocalMesh> mesh;  // the payload, for Loaded (kept alive for the upload)
};

struct LoaderCounters {
  std::uint64_t loadsStarted = 0;   // nodes whose first chunk was requested
  std::uint64_t loadsFinished = 0;  // nodes decoded and resident (hlod_0 included)
  std::uint64_t unloads = 0;
  std::uint64_t preemptions = 0;  // a load interrupted for a more important node
  std::uint64_t loadErrors = 0;   // read or decode failures (the node is not retried)
  std::uint64_t cacheHits = 0;    // nodes taken from the shared NodeCache without a read
  std::uint64_t bytesRead = 0;
  std::uint64_t requests = 0;       // reads that did not continue the previous one
  double latencyMs = 0.0;           // emulated latency waited for (what pipelining left)
  std::uint64_t residentBytes = 0;  // decoded bytes of resident nodes, a shared texture once
  std::uint64_t inFlightBytes = 0;  // memoryBytes reserved by loads in progress
  std::uint64_t capBytes = 0;       // LoaderParams::capBytes (0 = none)
  std::uint64_t peakBytes = 0;      // peak of residentBytes + inFlightBytes
  std::uint64_t residentNodes = 0;
  double residentCost = 0.0;    // sum of cost of resident nodes (for c_memory)
  bool rootsExceedCap = false;  // hlod_0 alone is larger than capBytes (cap not enforceable)
};

class Loader final : public Residency {
 public:
  Loader(const NodeSource& source, LoaderParams params = {});
  ~Loader() override;
  Loader(const Loader&) = delete;
  Loader& operator=(const Loader&) = delete;

  // Loads every hlod_0 node synchronously (before the first frame). Errors name the node; an
  // emulated link that would need more than kMaxRootLoadSeconds for it is an Error up front.
  static constexpr double kMaxRootLoadSeconds = 120.0;
  Status loadRoots();

  // Background thread: start() once, stop() (or the destructor) joins it.
  void start();
  void stop();
  bool running() const { return thread_.joinable(); }

  // This frame's priorities (Selection::loadPriorities): replaces the previous frame's set.
  void setWanted(std::span<const LoadRequest> requests);
  // Look-ahead for a known path (nodes selected for future cameras): replaces the previous
  // prefetch set. A node's priority is the larger of its wanted and prefetch priorities.
  void prefetch(std::span<const LoadRequest> requests);

  // One unit of work on the caller's thread: a chunk read, or the decode that finishes a node.
  // Returns false when there is nothing to do that fits in memory. Do not mix with start().
  bool step();

  bool isResident(std::uint32_t node) const override;
  std::shared_ptr<const LocalMesh> residentPayload(std::uint32_t node) const;
  // Loaded/Unloaded events since the last call, in order.
  std::vector<LoaderEvent> drainEvents();
  LoaderCounters counters() const;
  std::uint32_t currentLoad() const;  // the node being read, kNoNode when none
  std::string lastError() const;      // the last load error, "" when none

  // Settled mode: waits until all nodes are resident (true) or the timeout passes (false).
  // Only wanted/prefetched nodes get loaded. Without the thread it steps on the caller's thread.
  bool waitUntilResident(std::span<const std::uint32_t> nodes, std::chrono::milliseconds timeout);
  // Waits until nothing more can be loaded for the current wanted set (all loaded, or memory
  // full of more important nodes). Returns false on timeout.
  bool waitUntilIdle(std::chrono::milliseconds timeout);

 private:
  // Holds or releases the node's shared texture section (SharedTextures), keeping residentBytes,
  // where a section counts once.
  std::uint64_t holdTextureLocked(std::uint32_t node, const std::shared_ptr<const Image>& image);
  void releaseTextureLocked(std::uint32_t node);

  std::uint32_t chooseLocked();
  // Unloads what Eviction picks so that the node fits; false (nothing unloaded) when it cannot.
  bool makeRoomLocked(std::uint32_t node, double priority);
  void unloadLocked(std::uint32_t node);
  void dropPartialLocked(std::uint32_t node);
  void finishLocked(std::uint32_t node, Result<LocalMesh> mesh);
  void adoptLocked(std::uint32_t node, std::shared_ptr<const LocalMesh> mesh);
  void failLocked(std::uint32_t node, const std::string& why);
  // decodePayload, with an allocation failure (a forged decoded size) as an Error.
  Result<LocalMesh> decodeGuarded(std::uint32_t node, std::span<const std::byte> bytes);
  bool stopRequested();
  // Waits as the emulated link would for a read of len bytes at offset of node's payload;
  // stop() ends the wait at once.
  void throttle(std::uint32_t node, std::uint64_t offset, std::size_t len);
  // Requests the next ioRequests - 1 candidates after `chosen` (see LoaderParams::ioRequests).
  template <class Loadable>
  void issueAheadLocked(std::uint32_t chosen, Loadable&& loadable);
  void run();

  const NodeSource& source_;
  const Skeleton& skeleton_;
  LoaderParams params_;
  // The loader's parts (hlod/src/runtime/loader/). memory_ is constant; link_'s stream position
  // is the step's state (stepMutex_), its requests ahead are under mutex_; the others are under
  // mutex_.
  std::unique_ptr<NodeMemory> memory_;        // what a node reads and holds
  std::unique_ptr<LinkEmulator> link_;        // throttle and latency
  std::unique_ptr<SharedTextures> textures_;  // texture reference counts
  std::unique_ptr<PartialBuffers> partials_;  // loads in progress
  std::unique_ptr<LoadSchedule> schedule_;    // priorities and the order of loads
  std::unique_ptr<Eviction> eviction_;        // what to unload to make room

  mutable std::mutex mutex_;  // guards the parts above and everything below but residentFlag_
  std::unique_ptr<std::atomic<bool>[]> residentFlag_;
  std::vector<std::shared_ptr<const LocalMesh>> resident_;
  std::vector<std::uint8_t> isRoot_;
  std::vector<std::uint8_t> failed_;
  std::uint32_t current_ = kNoNode;
  std::uint32_t lastFinished_ = kNoNode;  // the node whose load completed last
  std::vector<LoaderEvent> events_;
  LoaderCounters counters_;
  std::string lastError_;
  bool idle_ = false;

  std::mutex stepMutex_;                // one step at a time
  std::condition_variable workCv_;      // new priorities, or stop
  std::condition_variable progressCv_;  // a node loaded, or idle
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace hlod
