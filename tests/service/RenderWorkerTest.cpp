// Render workers take turns at GL: no two tasks of different workers run at once, and a long
// task that yields between its frames lets a waiting worker's task in.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include "server/RenderWorker.h"

namespace service::server {
namespace {

using namespace std::chrono_literals;

std::unique_ptr<RenderWorker> startWorker(int index) {
  auto w = RenderWorker::start(index, renderer::Backend::Auto);
  if (!w) return nullptr;
  return std::move(*w);
}

TEST(RenderWorker, TasksOfDifferentWorkersNeverOverlap) {
  auto a = startWorker(0), b = startWorker(1);
  ASSERT_TRUE(a && b) << "no GL context";
  std::atomic<int> inside{0}, most{0};
  std::atomic<int> done{0};
  auto task = [&](renderer::GlContext&) {
    const int now = ++inside;
    int seen = most.load();
    while (now > seen && !most.compare_exchange_weak(seen, now)) {
    }
    std::this_thread::sleep_for(2ms);  // long enough for the other worker to try to enter
    --inside;
    ++done;
  };
  for (int i = 0; i < 20; ++i) {
    ASSERT_TRUE(a->post(task));
    ASSERT_TRUE(b->post(task));
  }
  a->stop();
  b->stop();
  EXPECT_EQ(done.load(), 40);
  EXPECT_EQ(most.load(), 1);
}

TEST(RenderWorker, ALongTaskThatYieldsLetsAnotherWorkersTaskIn) {
  auto runner = startWorker(0), worker = startWorker(1);
  ASSERT_TRUE(runner && worker) << "no GL context";
  std::promise<void> longStarted;
  std::atomic<bool> shortRan{false};
  std::atomic<int> framesBeforeShort{-1};
  ASSERT_TRUE(runner->post([&](renderer::GlContext&) {
    longStarted.set_value();
    // A "path job": frames until the other task has run, yielding after each; at most 10 s.
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    for (int frame = 0; std::chrono::steady_clock::now() < deadline; ++frame) {
      std::this_thread::sleep_for(1ms);
      if (shortRan) {
        framesBeforeShort = frame;
        return;
      }
      RenderWorker::yieldGl();
    }
  }));
  longStarted.get_future().wait();
  ASSERT_TRUE(worker->post([&](renderer::GlContext&) { shortRan = true; }));
  runner->stop();
  worker->stop();
  EXPECT_TRUE(shortRan.load());
  // It ran while the long task was still going (without the yields it would wait 10 s).
  EXPECT_GE(framesBeforeShort.load(), 0);
}

TEST(RenderWorker, YieldingOutsideATaskDoesNothing) {
  RenderWorker::yieldGl();  // the test's thread holds no turn: returns at once
  auto w = startWorker(0);
  ASSERT_TRUE(w) << "no GL context";
  std::promise<bool> ran;
  ASSERT_TRUE(w->post([&](renderer::GlContext&) { ran.set_value(true); }));
  auto f = ran.get_future();
  ASSERT_EQ(f.wait_for(30s), std::future_status::ready);
  EXPECT_TRUE(f.get());
}

}  // namespace
}  // namespace service::server
