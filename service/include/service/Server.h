#pragma once
// `hlodr serve`: the HTTP API of docs/api.md and the web page, over the node stores of a data
// folder. One process, many viewing sessions (docs/architecture.md, "The service"):
//   HTTP threads (cpp-httplib, a pool sized here) parse and validate, then post to
//   render workers 1..N (a GL context each, the sessions bound to it) and wait for their answer;
//   job runners (a GL context each) render path jobs, so long jobs never hold up frames.
// A bounded render queue answers 503 with Retry-After past --queue; at most --max-streams
// event streams at once. stop() shuts down gracefully: jobs are cancelled and close what they
// wrote (video, stats), sessions are destroyed on their workers.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "hlod/Result.h"
#include "renderer/GlContext.h"

namespace service {

struct ServerOptions {
  std::string bind = "127.0.0.1";
  int port = 8080;  // 0: any free port (bind() returns it)
  std::filesystem::path dataDir = "hlodr-data";
  std::filesystem::path webDir;   // the page's files; empty: none served
  std::filesystem::path jobsDir;  // empty: DATA/jobs
  int workers = 2;
  int jobRunners = 1;
  std::size_t maxSessions = 16;
  // Sessions asking for frames at once: share one budget, or queue for it (SessionManager.h).
  bool shareBudget = true;
  std::size_t queue = 32;                       // render requests waiting or running, all workers
  std::size_t maxStreams = 16;                  // event streams at once
  std::size_t maxJobs = 8;                      // queued or running
  std::uint64_t maxFrames = 5000;               // per job
  double keepJobsDays = 7.0;                    // finished jobs older than this go (0: never)
  std::uint64_t jobsMaxBytes = 0;               // the oldest finished jobs go past this (0: no cap)
  int maxSize = 4096;                           // largest frame side
  std::uint64_t cacheBytes = 1024ull << 20;     // decoded node payloads, all sessions together
  std::uint64_t glMemoryBytes = 4096ull << 20;  // render targets and GPU copies, all sessions
  int sessionIdleSeconds = 120;
  int requestTimeoutSeconds = 10;             // a request's head (and then its body) must arrive
  std::size_t maxConnectionsPerAddress = 64;  // open connections of one client; 0: no cap
  std::size_t maxConnections = 1000;          // open connections in all
  int renderTimeoutSeconds = 120;
  renderer::Backend backend = renderer::Backend::Auto;
  bool accessLog = true;
  // The clock of sessions' idle time (tests step one of their own).
  std::function<std::chrono::steady_clock::time_point()> clock = [] {
    return std::chrono::steady_clock::now();
  };
};

class Server {
 public:
  using Log = std::function<void(const std::string&)>;
  // Starts the workers (a GL context each) and opens the stores of the data folder.
  static hlod::Result<std::unique_ptr<Server>> create(const ServerOptions& options, Log log);
  ~Server();
  // Binds the listening socket; returns the port (the chosen one for port 0).
  hlod::Result<int> bind();
  // Serves until stop(); then shuts down gracefully.
  void run();
  // From any thread (a signal thread, a test): stops serving.
  void stop();
  // Draining: /healthz answers 503 so that a load balancer sends new sessions elsewhere, while
  // everything else is served as before (stop() follows after the grace period, serve --drain-s).
  void drain();
  // Closes the sessions idle longer than --session-idle-s by the options' clock, as the server
  // does every 2 s on its own; returns how many.
  std::size_t closeIdleSessions();
  // Holds every render worker until the returned handle goes: frames wait in the queue behind
  // it (a test that needs a full queue for certain, a drain before maintenance).
  std::shared_ptr<void> holdWorkers();
  std::string url() const;

 private:
  struct Impl;
  Server() = default;
  std::unique_ptr<Impl> impl_;
};

// The folder of the page: $HLODR_WEB_DIR, else share/hlodr/web beside the executable's folder
// (an installed hlodr), else web/ of the source tree this hlodr was built from. Empty when none
// holds an index.html.
std::filesystem::path findWebDir();

}  // namespace service
