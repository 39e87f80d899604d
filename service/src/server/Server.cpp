// `hlodr serve`: the parts of the server put together (see service/Server.h).
#include "service/Server.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <future>
#include <thread>

#include <sys/resource.h>

#include "renderer/VideoWriter.h"
#include "server/ApiReply.h"
#include "server/GlMemory.h"
#include "server/HttpApi.h"
#include "server/HttpServer.h"

namespace service {

namespace fs = std::filesystem;
using namespace server;

std::filesystem::path findWebDir() {
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("HLODR_WEB_DIR")) candidates.emplace_back(env);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path().parent_path() / "share" / "hlodr" / "web");
#ifdef HLODR_SOURCE_WEB_DIR
  candidates.emplace_back(HLODR_SOURCE_WEB_DIR);
#endif
  for (const auto& c : candidates)
    if (fs::exists(c / "index.html", ec)) return c;
  return {};
}

struct Server::Impl {
  ServerOptions options;
  Log log;
  Metrics metrics;
  std::unique_ptr<SceneRegistry> scenes;
  std::unique_ptr<GlMemory> glMemory;
  std::vector<std::unique_ptr<RenderWorker>> workers, runners;
  std::unique_ptr<SessionManager> sessions;
  std::unique_ptr<JobManager> jobs;
  std::unique_ptr<ApiContext> api;
  std::unique_ptr<HttpServer> http;
  int port = 0;
  std::thread reaper;
  std::mutex reaperMutex;
  std::condition_variable reaperCv;
  bool reaperStop = false;
  std::atomic<bool> stopped{false};
};

namespace {

// Each request's start, for the access log and the latency histogram: one request is served
// on one HTTP thread from routing to logging.
thread_local Clock::time_point requestStart;

}  // namespace

hlod::Result<std::unique_ptr<Server>> Server::create(const ServerOptions& o, Log log) {
  if (o.workers < 1 || o.workers > 64) return hlod::makeError("--workers must be in 1..64");
  if (o.jobRunners < 1 || o.jobRunners > 16)
    return hlod::makeError("--job-runners must be in 1..16");
  std::error_code ec;
  if (!fs::is_directory(o.dataDir, ec))
    return hlod::makeError("the data folder " + o.dataDir.string() + " does not exist");
  renderer::ignoreSigpipe();  // a client or an encoder gone away is an error, not a signal

  std::unique_ptr<Server> s(new Server());
  s->impl_ = std::make_unique<Impl>();
  Impl& m = *s->impl_;
  m.options = o;
  m.log = std::move(log);
  m.scenes = std::make_unique<SceneRegistry>(o.dataDir, o.cacheBytes);
  m.scenes->scan(m.log);
  for (int i = 0; i < o.workers; ++i) {
    auto w = RenderWorker::start(i, o.backend);
    if (!w) return hlod::makeError("render worker " + std::to_string(i) + ": " + w.message());
    if (i == 0) m.log("GL: " + renderer::describe((*w)->info()));
    m.workers.push_back(std::move(*w));
  }
  for (int i = 0; i < o.jobRunners; ++i) {
    auto w = RenderWorker::start(i, o.backend);
    if (!w) return hlod::makeError("job runner " + std::to_string(i) + ": " + w.message());
    m.runners.push_back(std::move(*w));
  }
  std::vector<RenderWorker*> workers, runners;
  for (auto& w : m.workers) workers.push_back(w.get());
  for (auto& w : m.runners) runners.push_back(w.get());

  SessionLimits sl;
  sl.maxSessions = o.maxSessions;
  sl.shareBudget = o.shareBudget;
  sl.idleTimeout = std::chrono::seconds(o.sessionIdleSeconds);
  sl.renderTimeout = std::chrono::seconds(o.renderTimeoutSeconds);
  sl.now = o.clock;
  m.glMemory = std::make_unique<GlMemory>(o.glMemoryBytes);
  m.sessions = std::make_unique<SessionManager>(workers, *m.scenes, m.metrics, *m.glMemory, sl);
  JobLimits jl;
  jl.maxJobs = o.maxJobs;
  jl.maxFrames = o.maxFrames;
  jl.keepDays = o.keepJobsDays;
  jl.maxBytes = o.jobsMaxBytes;
  const fs::path jobsDir = o.jobsDir.empty() ? o.dataDir / "jobs" : o.jobsDir;
  fs::create_directories(jobsDir, ec);
  if (!fs::is_directory(jobsDir, ec))
    return hlod::makeError("cannot create the jobs folder " + jobsDir.string());
  m.jobs = std::make_unique<JobManager>(runners, *m.scenes, m.metrics, jobsDir, jl);
  if (m.jobs->restored() > 0)
    m.log(std::to_string(m.jobs->restored()) + " job(s) of an earlier run listed again from " +
          jobsDir.string());

  m.api = std::make_unique<ApiContext>(*m.scenes, *m.sessions, *m.jobs, m.metrics, workers);
  ApiContext& api = *m.api;
  api.queueLimit = o.queue;
  api.maxStreams = o.maxStreams;
  api.maxSize = o.maxSize;
  api.log = m.log;
  api.accessLog = o.accessLog;

  // Metrics: counters that exist from the start, gauges read when scraped.
  for (const char* kind : {"render", "session", "job"})
    m.metrics.add("hlodr_frames_total", std::string("kind=\"") + kind + "\"", 0.0);
  m.metrics.help("hlodr_frames_total", "Frames rendered, by what asked for them");
  m.metrics.help("hlodr_http_requests_total", "HTTP requests answered, by method and status");
  m.metrics.help("hlodr_render_errors_total", "Frames that failed to render");
  m.metrics.help("hlodr_rejected_total", "Requests refused with 503, by the limit they hit");
  m.metrics.add("hlodr_render_errors_total", "", 0.0);
  Impl* impl = &m;
  auto one = [](double v) { return std::vector<std::pair<std::string, double>>{{"", v}}; };
  m.metrics.gauge("hlodr_queue_length", "Render requests waiting or running", "gauge",
                  [impl, one] { return one(double(impl->api->queued())); });
  m.metrics.gauge("hlodr_sessions", "Live viewing sessions", "gauge",
                  [impl, one] { return one(double(impl->sessions->count())); });
  m.metrics.gauge("hlodr_sessions_asking",
                  "Sessions that asked for a frame in the last second (they share one budget "
                  "under --admission share)",
                  "gauge", [impl, one] { return one(double(impl->sessions->asking())); });
  m.metrics.gauge("hlodr_jobs", "Path jobs by state", "gauge", [impl] {
    std::vector<std::pair<std::string, double>> out;
    for (const auto& [state, n] : impl->jobs->countByState())
      out.emplace_back("state=\"" + state + "\"", n);
    return out;
  });
  m.metrics.gauge("hlodr_event_streams", "Open job event streams", "gauge",
                  [impl, one] { return one(double(impl->api->streams.load())); });
  m.metrics.gauge("hlodr_resident_bytes", "Decoded node payloads in memory, all sessions", "gauge",
                  [impl, one] { return one(double(impl->scenes->cache()->liveBytes())); });
  m.metrics.gauge("hlodr_gl_bytes",
                  "GL memory of the sessions and warm contexts: render targets and GPU copies",
                  "gauge", [impl, one] { return one(double(impl->glMemory->used())); });
  m.metrics.gauge("hlodr_gl_cap_bytes", "Cap on the GL memory (--gl-memory-mb; 0: none)", "gauge",
                  [impl, one] { return one(double(impl->glMemory->cap())); });
  m.metrics.gauge("hlodr_cache_cap_bytes", "Cap on the decoded node payloads (0: none)", "gauge",
                  [impl, one] { return one(double(impl->scenes->cache()->capBytes())); });
  m.metrics.gauge("hlodr_loads_total", "Node payloads read and decoded", "counter",
                  [impl, one] { return one(double(impl->scenes->cache()->inserts())); });
  m.metrics.gauge("hlodr_loaded_bytes_total", "Decoded bytes of the loaded node payloads",
                  "counter",
                  [impl, one] { return one(double(impl->scenes->cache()->insertedBytes())); });
  m.metrics.gauge("hlodr_cache_hits_total", "Node loads served by another session's decoded copy",
                  "counter", [impl, one] { return one(double(impl->scenes->cache()->hits())); });

  // HTTP: threads for the event streams (each holds one while it lasts) plus room for the
  // requests that wait on a render; connections wait for their request in the Reception.
  ReceptionOptions ro;
  ro.threads = o.maxStreams + std::max<std::size_t>(8, o.queue / 2 + 2);
  ro.requestTimeout = std::chrono::seconds(o.requestTimeoutSeconds);
  ro.maxPerAddress = o.maxConnectionsPerAddress;
  ro.maxConnections = o.maxConnections;
  // Each connection is a file descriptor: leave room for the stores, jobs and encoders.
  rlimit files{};
  if (getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur != RLIM_INFINITY &&
      ro.maxConnections + 256 > files.rlim_cur) {
    ro.maxConnections = std::max<std::size_t>(16, std::size_t(files.rlim_cur) - 256);
    m.log("at most " + std::to_string(ro.maxConnections) + " connections (ulimit -n is " +
          std::to_string(files.rlim_cur) + ")");
  }
  m.http = std::make_unique<HttpServer>(ro, [impl](const char* reason) {
    impl->metrics.add("hlodr_rejected_total", std::string("reason=\"") + reason + "\"");
  });
  m.metrics.gauge("hlodr_connections", "Open client connections", "gauge",
                  [impl, one] { return one(double(impl->http->openConnections())); });
  m.http->set_payload_max_length(1 << 20);
  m.http->set_write_timeout(10, 0);
  m.http->set_keep_alive_max_count(1000);
  // A frame goes out as headers then body: with Nagle's algorithm the body waits for the
  // client's delayed ACK (40 ms on Linux), on the order of the frame's own time.
  m.http->set_tcp_nodelay(true);
  m.http->set_pre_routing_handler([](const httplib::Request& req, httplib::Response& res) {
    requestStart = Clock::now();
    // httplib decodes %00 into the path, and its file handler then opened the name up to the
    // NUL with the type of the whole name: /index.html%00.js served the page as JavaScript.
    for (const char c : req.path) {
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
        sendError(res, badRequest("the path holds a control character"));
        return httplib::Server::HandlerResponse::Handled;
      }
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  m.http->set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;
    const char* code = res.status == 404   ? "not_found"
                       : res.status == 413 ? "too_large"
                       : res.status == 405 ? "method_not_allowed"
                       : res.status >= 500 ? "internal"
                                           : "bad_request";
    const std::string message = res.status == 404   ? "no such route"
                                : res.status == 413 ? "the body is larger than 1 MiB"
                                                    : "the request was refused";
    res.set_content(nlohmann::json{{"error", {{"code", code}, {"message", message}}}}.dump(),
                    "application/json");
  });
  m.http->set_exception_handler(
      [impl](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
        std::string what = "unknown";
        try {
          std::rethrow_exception(ep);
        } catch (const std::exception& e) {
          what = e.what();
        } catch (...) {
        }
        impl->log("internal error on " + req.method + " " + req.path + ": " + what);
        res.status = 500;
        res.set_content(nlohmann::json{{"error", {{"code", "internal"}, {"message", what}}}}.dump(),
                        "application/json");
      });
  m.http->set_logger([impl](const httplib::Request& req, const httplib::Response& res) {
    const double ms = msSince(requestStart);
    impl->metrics.observeRequest(ms * 1e-3);
    impl->metrics.add("hlodr_http_requests_total",
                      "method=\"" + req.method + "\",code=\"" + std::to_string(res.status) + "\"");
    if (!impl->options.accessLog) return;
    std::string path = req.path.substr(0, 200);
    for (char& c : path)
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    char line[320];
    std::snprintf(line, sizeof line, "%s %s %d %.1f ms", req.method.c_str(), path.c_str(),
                  res.status, ms);
    impl->log(line);
  });
  installRoutes(*m.http, api);
  if (!o.webDir.empty()) {
    if (!m.http->set_mount_point("/", o.webDir.string()))
      return hlod::makeError("cannot serve the page from " + o.webDir.string());
    m.http->set_file_request_handler([](const httplib::Request&, httplib::Response& res) {
      res.set_header("Cache-Control", "no-cache");
    });
  }
  return s;
}

Server::~Server() {
  stop();
  if (impl_ && impl_->reaper.joinable()) impl_->reaper.join();
}

hlod::Result<int> Server::bind() {
  Impl& m = *impl_;
  m.port = m.http->bind(m.options.bind, m.options.port);
  if (m.port <= 0)
    return hlod::makeError("cannot listen on " + m.options.bind + ":" +
                           std::to_string(m.options.port) + " (in use, or not an address here)");
  return m.port;
}

std::string Server::url() const {
  const std::string host = impl_->options.bind == "0.0.0.0" ? "127.0.0.1" : impl_->options.bind;
  return "http://" + host + ":" + std::to_string(impl_->port) + "/";
}

void Server::run() {
  Impl& m = *impl_;
  m.reaper = std::thread([&m] {
    std::unique_lock lock(m.reaperMutex);
    while (!m.reaperStop) {
      m.reaperCv.wait_for(lock, std::chrono::seconds(2));
      if (m.reaperStop) break;
      lock.unlock();
      if (std::size_t n = m.sessions->expireIdle(); n > 0)
        m.log(std::to_string(n) + " idle session(s) closed");
      if (std::size_t n = m.jobs->expire(); n > 0)
        m.log(std::to_string(n) + " finished job(s) expired (--keep-jobs-days, --jobs-max-mb)");
      lock.lock();
    }
  });
  m.http->serve();  // until stop(); then the requests being served end
  // Stopped: shut down in order. Jobs first (their runners close the video and write the stats
  // of the frames so far), then sessions on their workers, then the workers.
  m.api->stopping = true;
  m.jobs->shutdown();
  m.sessions->shutdown();
  for (auto& w : m.workers) w->stop();
  {
    std::lock_guard lock(m.reaperMutex);
    m.reaperStop = true;
  }
  m.reaperCv.notify_all();
  if (m.reaper.joinable()) m.reaper.join();
  m.log("stopped");
}

std::size_t Server::closeIdleSessions() {
  return impl_->sessions->expireIdle();
}

std::shared_ptr<void> Server::holdWorkers() {
  auto gate = std::make_shared<std::promise<void>>();
  std::shared_future<void> open = gate->get_future().share();
  for (auto& w : impl_->workers) w->post([open](renderer::GlContext&) { open.wait(); });
  return std::shared_ptr<void>(nullptr, [gate](void*) { gate->set_value(); });
}

void Server::drain() {
  if (impl_) impl_->api->draining = true;
}

void Server::stop() {
  if (!impl_ || impl_->stopped.exchange(true)) return;
  impl_->api->stopping = true;
  // Cancel the jobs now: their event streams send their end event (within a frame and a
  // second) before the sockets close.
  for (const auto& j : impl_->jobs->list()) j->cancel = true;
  const auto deadline = Clock::now() + std::chrono::seconds(3);
  while (impl_->api->streams.load() > 0 && Clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  impl_->http->stop();
}

}  // namespace service
