#include "server/RenderWorker.h"

#include <future>

namespace service::server {

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
  auto context = renderer::createContext(backend);
  if (!context) {
    started->set_value(context.error());
    return;
  }
  info_ = (*context)->info();
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
    (*context)->makeCurrent();
    task(**context);
    std::lock_guard lock(mutex_);
    --running_;
  }
  // What the tasks left bound to this context (sessions) was destroyed by them; the context
  // goes now, on its own thread.
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
