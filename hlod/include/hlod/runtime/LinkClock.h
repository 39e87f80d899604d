#pragma once
// The time the loader's emulated link runs on (LoaderParams::clock, LoaderParams::ioMbps and
// ioLatencyMs). The link reads the time when a request goes ahead and when it is served (the
// latency that pipelining left), and waits on the clock for the emulated latency and transfer.
// The default is the steady clock and a real wait; a test's clock can move its own time forward
// in waitFor and return at once, so that throttling and latency run without sleeping.
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>

namespace hlod {

class LinkClock {
 public:
  using TimePoint = std::chrono::steady_clock::time_point;
  using Milliseconds = std::chrono::duration<double, std::milli>;

  virtual ~LinkClock() = default;
  virtual TimePoint now() = 0;
  // Waits `duration` with `lock` held on entry and on return, and returns early once `stopped()`
  // holds (read under the lock; `wake` is notified whenever it may have turned true). Returns
  // stopped().
  virtual bool waitFor(std::unique_lock<std::mutex>& lock, std::condition_variable& wake,
                       Milliseconds duration, const std::function<bool()>& stopped) = 0;
};

// A time point as microseconds since the clock's epoch: FrameTimeline's unit (FrameStats.h).
inline double microsecondsOf(LinkClock::TimePoint t) {
  return std::chrono::duration<double, std::micro>(t.time_since_epoch()).count();
}

// std::chrono::steady_clock, and a wait on the condition variable.
class SteadyLinkClock final : public LinkClock {
 public:
  TimePoint now() override { return std::chrono::steady_clock::now(); }
  bool waitFor(std::unique_lock<std::mutex>& lock, std::condition_variable& wake,
               Milliseconds duration, const std::function<bool()>& stopped) override {
    return wake.wait_for(lock, duration, stopped);
  }
};

}  // namespace hlod
