#pragma once
// Work prepared in parallel and committed in order (private to the builder): the blocks of a
// build, the cells of one quadtree level. The store does not depend on the thread count.
#include <algorithm>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "hlod/Result.h"

namespace hlod {

// Prepares items 0..count-1 on `threads` workers (0: one per core) and commits them in order on
// the calling thread. A worker starts item i only when fewer than 2 x threads items wait to be
// committed: memory is bounded by the items in flight. An error (or an exception, such as
// bad_alloc) stops the workers and is returned; `what` names an item in such a message.
template <class T>
Status prepareInOrder(std::size_t count, unsigned threads,
                      const std::function<Result<T>(std::size_t)>& prepare,
                      const std::function<Status(std::size_t, T&&)>& commit,
                      const char* what = "item") {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  threads = unsigned(std::min<std::size_t>(threads, std::max<std::size_t>(1, count)));
  const std::size_t window = 2 * std::size_t(threads);
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<std::optional<Result<T>>> slots(count);
  std::size_t next = 0, done = 0;  // next item to start; items committed
  bool stop = false;
  const auto work = [&] {
    for (;;) {
      std::size_t i;
      {
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return stop || next >= count || next < done + window; });
        if (stop || next >= count) return;
        i = next++;
      }
      Result<T> r = makeError("not prepared");
      try {
        r = prepare(i);
      } catch (const std::exception& e) {
        r = makeError(std::string(what) + " " + std::to_string(i) + ": " + e.what());
      }
      std::lock_guard lock(mutex);
      slots[i] = std::move(r);
      changed.notify_all();
    }
  };
  std::vector<std::thread> workers;
  for (unsigned t = 0; t < threads; ++t) workers.emplace_back(work);
  Status status = Ok{};
  for (std::size_t i = 0; i < count && status; ++i) {
    Result<T> item = makeError("");
    {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return slots[i].has_value(); });
      item = std::move(*slots[i]);
      slots[i].reset();
    }
    status = item ? commit(i, std::move(*item)) : Status(item.error());
    std::lock_guard lock(mutex);
    ++done;
    if (!status) stop = true;
    changed.notify_all();
  }
  for (std::thread& w : workers) w.join();
  return status;
}

}  // namespace hlod
