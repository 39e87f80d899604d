// Decoded node payloads shared across sessions. See hlod/runtime/NodeCache.h.
#include "hlod/runtime/NodeCache.h"

#include <atomic>
#include <cassert>
#include <vector>

namespace hlod {

// Payloads report their death here (their deleter runs on whichever thread drops the last
// reference, possibly with the cache's mutex held): an atomic, so it never takes a lock.
struct NodeCache::Shared {
  std::atomic<std::uint64_t> aliveBytes{0};
};

NodeCache::NodeCache(std::uint64_t capBytes)
    : capBytes_(capBytes), shared_(std::make_shared<Shared>()) {}

NodeCache::~NodeCache() = default;

std::shared_ptr<const LocalMesh> NodeCache::find(std::uint64_t key) {
  std::lock_guard lock(mutex_);
  auto it = entries_.find(key);
  if (it == entries_.end()) return nullptr;
  std::shared_ptr<const LocalMesh> mesh = it->second.mesh.lock();
  if (!mesh) {
    entries_.erase(it);
    return nullptr;
  }
  ++hits_;
  keepLocked(key, it->second, mesh);
  return mesh;
}

bool NodeCache::reserve(std::uint64_t bytes) {
  std::lock_guard lock(mutex_);
  if (capBytes_ > 0) {
    trimLocked(bytes);
    if (shared_->aliveBytes.load() + reserved_ + bytes > capBytes_) return false;
  }
  reserved_ += bytes;
  return true;
}

void NodeCache::release(std::uint64_t bytes) {
  std::lock_guard lock(mutex_);
  assert(bytes <= reserved_);
  reserved_ -= bytes;
}

std::shared_ptr<const LocalMesh> NodeCache::insert(std::uint64_t key, LocalMesh mesh,
                                                   std::uint64_t bytes) {
  std::lock_guard lock(mutex_);
  assert(bytes <= reserved_);
  reserved_ -= bytes;
  Entry& e = entries_[key];
  if (auto there = e.mesh.lock()) {
    // Another session decoded it first: share that copy, drop this one.
    keepLocked(key, e, there);
    return there;
  }
  shared_->aliveBytes += bytes;
  ++inserts_;
  insertedBytes_ += bytes;
  std::shared_ptr<const LocalMesh> fresh(new LocalMesh(std::move(mesh)),
                                         [shared = shared_, bytes](const LocalMesh* m) {
                                           shared->aliveBytes -= bytes;
                                           delete m;
                                         });
  e.mesh = fresh;
  e.bytes = bytes;
  keepLocked(key, e, fresh);
  return fresh;
}

void NodeCache::keepLocked(std::uint64_t key, Entry& e, std::shared_ptr<const LocalMesh> mesh) {
  // Without a cap nothing is kept beyond the sessions' own references: sharing only.
  if (capBytes_ == 0) return;
  if (e.kept) keptOrder_.erase(e.lru);
  keptOrder_.push_front(key);
  e.lru = keptOrder_.begin();
  e.kept = std::move(mesh);
}

void NodeCache::trimLocked(std::uint64_t need) {
  // Oldest kept entries that no session holds any more go first; held ones stay (dropping the
  // cache's reference would free nothing).
  std::vector<std::shared_ptr<const LocalMesh>> dropped;  // freed after the scan
  for (auto it = keptOrder_.end(); it != keptOrder_.begin();) {
    if (shared_->aliveBytes.load() + reserved_ + need <= capBytes_) break;
    --it;
    auto entry = entries_.find(*it);
    assert(entry != entries_.end() && entry->second.kept);
    if (entry->second.kept.use_count() > 1) continue;
    dropped.push_back(std::move(entry->second.kept));
    entries_.erase(entry);
    it = keptOrder_.erase(it);
    dropped.clear();  // the payload dies here, its deleter lowers aliveBytes
  }
}

std::uint64_t NodeCache::liveBytes() const {
  std::lock_guard lock(mutex_);
  return shared_->aliveBytes.load() + reserved_;
}

std::uint64_t NodeCache::hits() const {
  std::lock_guard lock(mutex_);
  return hits_;
}

std::uint64_t NodeCache::inserts() const {
  std::lock_guard lock(mutex_);
  return inserts_;
}

std::uint64_t NodeCache::insertedBytes() const {
  std::lock_guard lock(mutex_);
  return insertedBytes_;
}

}  // namespace hlod
