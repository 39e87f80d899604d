#pragma once
// Decoded node payloads shared by the viewing sessions of a server (docs/architecture.md, "The
// service"): a node that one session has decoded is handed to the next session that wants it
// without a second read or decode, and the decoded bytes of all sessions together stay under one
// cap.
//
// Reference counted: a payload stays alive while any session holds it (its Loader's resident
// set, a queued upload) and, once none does, while the cache keeps it among its recently used
// entries. liveBytes() counts every distinct payload alive, held or kept, plus the reservations
// of loads in progress; reserve() first drops kept entries that no session holds, oldest first.
// A cap of 0 means none. Thread-safe: the loader threads of many sessions call it at once.
// Keys are (store, node) pairs, so that the stores of one server share one cap.
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "hlod/Mesh.h"

namespace hlod {

class NodeCache {
 public:
  explicit NodeCache(std::uint64_t capBytes = 0);
  ~NodeCache();
  NodeCache(const NodeCache&) = delete;
  NodeCache& operator=(const NodeCache&) = delete;

  static std::uint64_t key(std::uint32_t store, std::uint32_t node) {
    return (std::uint64_t(store) << 32) | node;
  }
  // The decoded payload of key if it is alive (held by a session or kept), else null.
  std::shared_ptr<const LocalMesh> find(std::uint64_t key);
  // Makes room for a load of `bytes` (decoded): true when liveBytes() + bytes fits the cap after
  // dropping kept entries no session holds; the bytes then count as reserved until insert() or
  // release().
  bool reserve(std::uint64_t bytes);
  void release(std::uint64_t bytes);
  // Adopts a decoded payload of `bytes` that was reserved: returns the shared copy (the one
  // already there if another session inserted it meanwhile).
  std::shared_ptr<const LocalMesh> insert(std::uint64_t key, LocalMesh mesh, std::uint64_t bytes);

  std::uint64_t liveBytes() const;
  std::uint64_t capBytes() const { return capBytes_; }
  std::uint64_t hits() const;
  std::uint64_t inserts() const;        // payloads decoded and adopted (server-wide loads)
  std::uint64_t insertedBytes() const;  // their decoded bytes

 private:
  struct Entry {
    std::weak_ptr<const LocalMesh> mesh;
    std::uint64_t bytes = 0;
    std::list<std::uint64_t>::iterator lru;  // position in keptOrder_ when kept
    std::shared_ptr<const LocalMesh> kept;   // the cache's own reference, if kept
  };
  struct Shared;  // outlives the cache while payloads do: their deleters report to it
  void keepLocked(std::uint64_t key, Entry& e, std::shared_ptr<const LocalMesh> mesh);
  void trimLocked(std::uint64_t need);

  const std::uint64_t capBytes_;
  std::shared_ptr<Shared> shared_;
  std::unordered_map<std::uint64_t, Entry> entries_;
  std::list<std::uint64_t> keptOrder_;  // most recently used first
  std::uint64_t reserved_ = 0;
  std::uint64_t hits_ = 0;
  std::uint64_t inserts_ = 0;
  std::uint64_t insertedBytes_ = 0;
  mutable std::mutex mutex_;
};

}  // namespace hlod
