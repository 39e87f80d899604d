#pragma once
// A render worker: one thread owning one GL context, running the tasks posted to it in order
// with the context current. The sessions bound to a worker live and die on its thread; HTTP
// threads only post tasks and wait for their own answer.
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "hlod/Result.h"
#include "renderer/GlContext.h"

namespace service::server {

class RenderWorker {
 public:
  using Task = std::function<void(renderer::GlContext&)>;

  // Starts the thread and creates its context there; an Error when no GL context can be made.
  static hlod::Result<std::unique_ptr<RenderWorker>> start(int index, renderer::Backend backend);
  ~RenderWorker();  // stop()
  RenderWorker(const RenderWorker&) = delete;
  RenderWorker& operator=(const RenderWorker&) = delete;

  // Runs task on the worker's thread, after the ones posted before it. After stop() the task is
  // dropped (return false).
  bool post(Task task);
  std::size_t queued() const;  // waiting or running
  // Runs the tasks already queued, then ends the thread (its context dies with it).
  void stop();
  const renderer::ContextInfo& info() const { return info_; }
  // Workers take turns at GL, a task at a time. A long task (a path job, a study) calls this
  // between its frames to let the others have a turn; elsewhere it does nothing.
  static void yieldGl();
  int index() const { return index_; }

 private:
  RenderWorker() = default;
  void run(renderer::Backend backend, std::promise<hlod::Status>* started);

  int index_ = 0;
  renderer::ContextInfo info_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Task> tasks_;
  std::size_t running_ = 0;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace service::server
