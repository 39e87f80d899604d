#include "server/RenderWorker.h"

#include <cstdint>
#include <future>

namespace service::server {
namespace {

// The process's GL turn: one worker at a time issues GL calls. Mesa's llvmpipe (Debian 12's
// 22.3) crashed inside glDrawElements when several contexts drew on their own threads at once
// (docs/known-issues.md), and it shares one rasteriser among its contexts anyway. A ticket
// lock: workers get their turns in the order they asked, so a path job that yields between
// frames cannot take the next turn back before a waiting session frame.
class GlTurn {
 public:
  void acquire() {
    std::unique_lock lock(mutex_);
    const std::uint64_t ticket = next_++;
    cv_.wait(lock, [&] { return serving_ == ticket; });
  }
  void release() {
    {
      std::lock_guard lock(mutex_);
      ++serving_;
    }
    cv_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::uint64_t next_ = 0, serving_ = 0;
};

GlTurn& glTurn() {
  static GlTurn turn;
  return turn;
}
thread_local bool holdsGlTurn = false;

class HeldGlTurn {
 public:
  HeldGlTurn() {
    glTurn().acquire();
    holdsGlTurn = true;
  }
  ~HeldGlTurn() {
    holdsGlTurn = false;
    glTurn().release();
  }
  HeldGlTurn(const HeldGlTurn&) = delete;
  HeldGlTurn& operator=(const HeldGlTurn&) = delete;
};

}  // namespace

void RenderWorker::yieldGl() {
  if (!holdsGlTurn) return;
  glTurn().release();
  glTurn().acquire();
}

hlod::Result<std::unique_ptr<RenderWorker>> RenderWorker::start(int index,
                                                                renderer::Backend backend) {
  std::unique_ptr<RenderWorker> w(new RenderWorker());
  w->index_ = index;
  std::promise<hlod::Status> started;
  auto ready = started.get_future();
  w->thread_ = std::thread([raw = w.get(), backend, &started] { raw->run(backend, &started); });
  hlod::Status s = ready.get();
  if (!s) {
    w->thread_.join();
    return s.error();
  }
  return w;
}

RenderWorker::~RenderWorker() {
  stop();
}

void RenderWorker::run(renderer::Backend backend, std::promise<hlod::Status>* started) {
  auto context = [&] {
    const HeldGlTurn turn;
    auto made = renderer::createContext(backend);
    if (made) info_ = (*made)->info();
    return made;
  }();
  if (!context) {
    started->set_value(context.error());
    return;
  }
  started->set_value(hlod::Ok{});
  for (;;) {
    Task task;
    {
      std::unique_lock lock(mutex_);
      cv_.wait(lock, [&] { return stopping_ || !tasks_.empty(); });
      if (tasks_.empty()) break;  // stopping, and nothing left
      task = std::move(tasks_.front());
      tasks_.pop_front();
      ++running_;
    }
    {
      const HeldGlTurn turn;
      (*context)->makeCurrent();
      task(**context);
    }
    std::lock_guard lock(mutex_);
    --running_;
  }
  // What the tasks left bound to this context (sessions) was destroyed by them; the context
  // goes now, on its own thread.
  const HeldGlTurn turn;
  context->reset();
}

bool RenderWorker::post(Task task) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return false;
    tasks_.push_back(std::move(task));
  }
  cv_.notify_one();
  return true;
}

std::size_t RenderWorker::queued() const {
  std::lock_guard lock(mutex_);
  return tasks_.size() + running_;
}

void RenderWorker::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

}  // namespace service::server
