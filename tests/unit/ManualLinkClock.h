#pragma once
// LinkClocks (hlod/runtime/LinkClock.h) for tests: the emulated link's throttling and latency run
// without sleeping, and the time they took is exact.
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>

#include "hlod/runtime/LinkClock.h"

namespace hlod::test {

// Time moves only when the loader waits on the clock (at once, by what it waits) or the test
// advances it: for loaders stepped on the test's thread.
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

// For a loader on its own thread: once close()d, a wait on the link holds the loader thread (with
// the loader's lock released, as a real wait does) until the test lets it pass with release(),
// which moves the time on by what it waited. The test then knows where the loader thread is:
// parked mid-load. Before close() waits pass at once (loadRoots on the test's thread).
class GatedLinkClock final : public LinkClock {
 public:
  enum class Parked { OnTheLink, Idle, NotWithinAMinute };

  void close() {
    std::lock_guard own(mutex_);
    closed_ = true;
  }

  TimePoint now() override {
    std::lock_guard lock(mutex_);
    return now_;
  }
  bool waitFor(std::unique_lock<std::mutex>& lock, std::condition_variable& wake,
               Milliseconds duration, const std::function<bool()>& stopped) override {
    {
      std::lock_guard own(mutex_);
      if (!closed_) {
        now_ += std::chrono::duration_cast<std::chrono::steady_clock::duration>(duration);
        return stopped();
      }
      waiting_ = true;
      released_ = false;
      waitedMs_ = duration;
      loaderMutex_ = lock.mutex();
      loaderWake_ = &wake;
    }
    parkedCv_.notify_all();
    // released_ is set under the loader's mutex (release()), so this wait cannot miss it.
    wake.wait(lock, [&] { return released_ || stopped(); });
    std::lock_guard own(mutex_);
    waiting_ = false;
    return !released_;
  }

  // Waits until the loader thread waits on the link (OnTheLink), or idle() holds (Idle). The
  // minute bounds a deadlock, not a time: a loader that does neither is a failure.
  Parked awaitParkedOr(const std::function<bool()>& idle) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(1);
    for (;;) {
      {
        std::unique_lock own(mutex_);
        if (parkedCv_.wait_for(own, std::chrono::milliseconds(1), [&] { return waiting_; }))
          return Parked::OnTheLink;
      }
      if (idle()) return Parked::Idle;
      if (std::chrono::steady_clock::now() > deadline) return Parked::NotWithinAMinute;
    }
  }

  // Lets the parked wait pass, the time moved on by what it waited.
  void release() {
    std::mutex* loaderMutex;
    std::condition_variable* loaderWake;
    {
      std::lock_guard own(mutex_);
      if (!waiting_) return;
      waiting_ = false;  // from now on the loader thread is on its way, not parked
      now_ += std::chrono::duration_cast<std::chrono::steady_clock::duration>(waitedMs_);
      loaderMutex = loaderMutex_;
      loaderWake = loaderWake_;
    }
    {
      std::lock_guard loader(*loaderMutex);
      released_ = true;
    }
    loaderWake->notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable parkedCv_;
  TimePoint now_{};
  bool closed_ = false;
  bool waiting_ = false;
  bool released_ = false;  // written under the loader's mutex while a wait is parked
  Milliseconds waitedMs_{0};
  std::mutex* loaderMutex_ = nullptr;
  std::condition_variable* loaderWake_ = nullptr;
};

}  // namespace hlod::test
