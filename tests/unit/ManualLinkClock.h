#pragma once
// A LinkClock (hlod/runtime/LinkClock.h) whose time moves only when the loader waits on it or the
// test advances it: the emulated link's throttling and latency run without sleeping, and the
// time they took is exact.
#include <mutex>

#include "hlod/runtime/LinkClock.h"

namespace hlod::test {

class ManualLinkClock final : public LinkClock {
 public:
  TimePoint now() override {
    std::lock_guard lock(mutex_);
    return now_;
  }
  // The wait passes at once: the clock moves on by `duration`, unless stopped already.
  bool waitFor(std::unique_lock<std::mutex>&, std::condition_variable&, Milliseconds duration,
               const std::function<bool()>& stopped) override {
    if (stopped()) return true;
    advance(duration);
    return false;
  }
  void advance(Milliseconds duration) {
    std::lock_guard lock(mutex_);
    now_ += std::chrono::duration_cast<std::chrono::steady_clock::duration>(duration);
  }
  // Milliseconds since the clock started.
  double elapsedMs() { return Milliseconds(now() - TimePoint{}).count(); }

 private:
  std::mutex mutex_;
  TimePoint now_{};
};

}  // namespace hlod::test
