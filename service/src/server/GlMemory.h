#pragma once
// The server's GL memory, counted against one cap (--gl-memory-mb): each session and warm
// render context holds a lease for its render targets (colour, depth, shadow map, SSAO: known
// before it is made, renderer::Renderer::targetBytes) and, once it draws, for its GPU copies of
// the nodes (vertex buffers, textures). A session whose targets do not fit is refused (503 and
// the reason) instead of making the process grow past what the machine has; a session's lease
// ends when the session is destroyed, with its GL objects.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>

namespace service::server {

class GlMemory {
 public:
  explicit GlMemory(std::uint64_t capBytes) : cap_(capBytes) {}

  class Lease {
   public:
    Lease() = default;
    Lease(Lease&& o) noexcept : owner_(o.owner_), bytes_(o.bytes_) { o.owner_ = nullptr; }
    Lease& operator=(Lease&& o) noexcept;
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    ~Lease() { release(); }
    // The holder's bytes now (a session's targets plus its GPU copies, after a frame). Growth
    // is not refused: a session's geometry is bounded by its loader's cap; new sessions see it.
    void resize(std::uint64_t bytes);
    std::uint64_t bytes() const { return bytes_; }
    void release();

   private:
    friend class GlMemory;
    Lease(GlMemory* owner, std::uint64_t bytes) : owner_(owner), bytes_(bytes) {}
    GlMemory* owner_ = nullptr;
    std::uint64_t bytes_ = 0;
  };

  // A lease of `bytes`, or none when they do not fit under the cap (0: no cap).
  std::optional<Lease> reserve(std::uint64_t bytes);
  std::uint64_t used() const { return used_.load(); }
  std::uint64_t cap() const { return cap_; }

 private:
  std::uint64_t cap_;
  std::mutex mutex_;
  std::atomic<std::uint64_t> used_{0};
};

}  // namespace service::server
