#pragma once
// The emulated link between the loader and its store (LoaderParams::ioMbps, ioLatencyMs,
// ioRequests): a read waits for the link's transfer time at ioMbps, and a read that starts a new
// request (one that does not continue where the previous read ended in the payload file, as the
// next chunk of a node or a sibling stored right after it does) waits for its latency first.
// Requests are pipelined as an HTTP/2 client or a disk queue keeps them: while one node streams,
// the next ioRequests - 1 loadable nodes are requested already (requestAhead), so that their
// latency runs during that transfer; a node that drops out of the window is cancelled and pays
// its full latency if it comes back.
//
// Time is the LinkClock's (hlod/runtime/LinkClock.h), so that tests can run the link without
// sleeping. Private to the loader (runtime/Loader.cpp). Not locked: the stream position is the
// loading step's state (the Loader's step lock), the requests ahead are read and written under the
// Loader's mutex.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <unordered_map>

#include "hlod/runtime/LinkClock.h"

namespace hlod {

class LinkEmulator {
 public:
  // A null clock is the steady clock.
  LinkEmulator(double mbps, double latencyMs, std::size_t requests,
               std::shared_ptr<LinkClock> clock);

  // A transfer time per byte (ioMbps > 0), a latency per request (ioLatencyMs > 0).
  bool throttled() const { return mbps_ > 0.0; }
  bool hasLatency() const { return latencyMs_ > 0.0; }
  // Seconds the link needs at least for `bytes` in `requests` requests of their own.
  double seconds(std::uint64_t bytes, std::size_t requests) const;

  // How many nodes besides the one streaming are requested ahead: ioRequests - 1.
  std::size_t window() const;
  // The nodes now requested ahead of `chosen`, the one about to stream (at most window() of them,
  // in priority order). A node requested before keeps its request's time, a new one is requested
  // now; the others are cancelled, except `chosen`, whose request is served by its first read.
  void requestAhead(std::uint32_t chosen, std::span<const std::uint32_t> ahead);
  // Nothing stays requested (the loader is idle).
  void cancelAhead();

  // Records a read of `len` bytes at offset `at` of the payload file: true when it continues the
  // previous read (the same request), false when it starts a new one.
  bool continues(std::uint64_t at, std::size_t len);
  // The latency a new request of `node` waits at `now`: ioLatencyMs, less the time since the node
  // was requested ahead (that request is then served).
  double latencyMs(std::uint32_t node, LinkClock::TimePoint now);
  // The transfer time of `len` bytes.
  double transferMs(std::size_t len) const;

  LinkClock& clock() { return *clock_; }

 private:
  double mbps_, latencyMs_;
  std::size_t requests_;
  std::shared_ptr<LinkClock> clock_;
  std::uint64_t streamEnd_ = ~0ull;  // payload file offset where the last read ended
  // Nodes requested ahead, with the time their request went out.
  std::unordered_map<std::uint32_t, LinkClock::TimePoint> ahead_;
};

}  // namespace hlod
