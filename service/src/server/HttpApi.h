#pragma once
// The routes of docs/api.md on a cpp-httplib server, over the server's parts.
#include <atomic>
#include <cstddef>

#include <httplib.h>

#include "server/Jobs.h"
#include "server/Metrics.h"
#include "server/RenderWorker.h"
#include "server/SceneRegistry.h"
#include "server/SessionManager.h"

namespace service::server {

struct ApiContext {
  ApiContext(SceneRegistry& s, SessionManager& se, JobManager& j, Metrics& m,
             std::vector<RenderWorker*> w)
      : scenes(s), sessions(se), jobs(j), metrics(m), workers(std::move(w)) {}
  SceneRegistry& scenes;
  SessionManager& sessions;
  JobManager& jobs;
  Metrics& metrics;
  std::vector<RenderWorker*> workers;
  std::size_t queueLimit = 32;
  std::size_t maxStreams = 16;
  int maxSize = 4096;
  std::atomic<std::size_t> streams{0};
  std::atomic<std::size_t> inFlight{0};  // render requests admitted and not yet answered
  std::atomic<bool> stopping{false};
  std::atomic<bool> draining{false};  // /healthz says 503 (Server::drain)
  std::function<void(const std::string&)> log;
  bool accessLog = true;
  std::size_t queued() const;  // render requests waiting or running
};

void installRoutes(httplib::Server& http, ApiContext& api);

}  // namespace service::server
