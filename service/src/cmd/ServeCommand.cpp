// `hlodr serve`: the HTTP service and its page over the node stores of a data folder.
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <thread>

#include "cmd/Commands.h"
#include "hlod/builder/Calibration.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/city/City.h"
#include "service/Args.h"
#include "service/Progress.h"
#include "service/Server.h"

namespace service::cmd {

namespace fs = std::filesystem;

const char* const kServeUsage =
    "usage: hlodr serve [--port 8080] [--bind 127.0.0.1] [--data DIR] [options]\n"
    "\n"
    "Serves the HTTP API (docs/api.md) and the web page over the node stores in DIR (each\n"
    "NAME.hlod/ folder is scene NAME). When DIR holds no store, it generates the default city\n"
    "(DIR/city/) and builds its store (DIR/city.hlod/) first, once. Open the printed URL.\n"
    "SIGINT or SIGTERM stop it gracefully: running jobs are cancelled and close their files.\n"
    "\n"
    "options:\n"
    "  --port N             TCP port (default 8080; 0: any free port)\n"
    "  --bind ADDR          address to listen on (default 127.0.0.1; 0.0.0.0 for all)\n"
    "  --data DIR           the data folder (default hlodr-data; created if missing)\n"
    "  --workers N          render workers, one GL context each (default 2)\n"
    "  --job-runners N      path-job runners, one GL context each (default 1)\n"
    "  --max-sessions N     live viewing sessions at once (default 16)\n"
    "  --queue N            render requests waiting or running; past it 503 (default 32)\n"
    "  --max-streams N      job event streams at once; past it 503 (default 16)\n"
    "  --max-jobs N         jobs queued or running at once (default 8)\n"
    "  --max-frames N       frames of one job (default 5000)\n"
    "  --max-size N         largest frame side in pixels (default 4096)\n"
    "  --memory-mb N        decoded node payloads of all sessions together (default 1024)\n"
    "  --session-idle-s S   close sessions idle this long (default 120)\n"
    "  --web DIR            the page's files (default: found beside hlodr or in its source)\n"
    "  --jobs-dir DIR       where jobs write their frames, videos and stats (default DIR/jobs)\n"
    "  --quiet              no access log\n"
    "\n"
    "environment: HLODR_GL_BACKEND=egl|osmesa forces a GL backend.\n";

namespace {

void logLine(const std::string& line) {
  char stamp[32];
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  std::strftime(stamp, sizeof stamp, "%H:%M:%S", &tm);
  std::fprintf(stderr, "[%s] %s\n", stamp, line.c_str());
  std::fflush(stderr);
}

bool hasStore(const fs::path& dir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".hlod" && fs::exists(e.path() / "skeleton.bin", ec)) return true;
  return false;
}

// The default scene, made once: the procedural city and its node store.
hlod::Status makeDefaultCity(const fs::path& dir) {
  const fs::path city = dir / "city", store = dir / "city.hlod";
  if (!hlod::isCityFolder(city)) {
    logLine("no scene in " + dir.string() + ": generating the default city into " + city.string());
    ProgressLine progress("city", false);
    auto s = hlod::writeCity(city, hlod::CityOptions{}, [&](const hlod::CityProgress& p) {
      progress.update(
          double(p.blocksDone) / std::max(1, p.blocksTotal),
          std::to_string(p.blocksDone) + "/" + std::to_string(p.blocksTotal) + " blocks");
    });
    progress.done();
    if (!s) return s;
  }
  logLine("building its HLOD store " + store.string());
  hlod::BuildOptions options;
  // A malformed calibration file is an error here too, as in `hlodr build`.
  const auto calibrated = hlod::readCalibratedCTex();
  if (!calibrated) return calibrated.error();
  if (calibrated->has_value()) options.cTex = **calibrated;
  ProgressLine progress("build", false);
  auto built = hlod::buildStoreFromCity(city, store, options, [&](const hlod::BuildProgress& p) {
    progress.update(double(p.blocksDone) / double(std::max<std::size_t>(1, p.blockCount)),
                    std::to_string(p.blocksDone) + "/" + std::to_string(p.blockCount) + " blocks");
  });
  progress.done();
  if (!built) return built.error();
  logLine("built " + store.string() + ": " + std::to_string(built->nodes.size()) + " nodes");
  return hlod::Ok{};
}

}  // namespace

int runServe(const Argv& argv) {
  auto args = Args::parse(
      argv, {"quiet"},
      {"port", "bind", "data", "workers", "job-runners", "max-sessions", "queue", "max-streams",
       "max-jobs", "max-frames", "max-size", "memory-mb", "session-idle-s", "web", "jobs-dir"});
  if (!args) {
    std::fprintf(stderr, "hlodr serve: %s\n%s", args.message().c_str(), kServeUsage);
    return 2;
  }
  if (!args->positionals().empty()) {
    std::fprintf(stderr, "hlodr serve: unexpected argument '%s' (the data folder is --data DIR)\n",
                 args->positionals()[0].c_str());
    return 2;
  }
  ServerOptions o;
  auto port = args->integer("port", 8080, 0, 65535);
  auto workers = args->integer("workers", 2, 1, 64);
  auto runners = args->integer("job-runners", 1, 1, 16);
  auto sessions = args->integer("max-sessions", 16, 1, 10000);
  auto queue = args->integer("queue", 32, 1, 100000);
  auto streams = args->integer("max-streams", 16, 1, 10000);
  auto jobs = args->integer("max-jobs", 8, 1, 10000);
  auto frames = args->integer("max-frames", 5000, 1, 10000000);
  auto size = args->integer("max-size", 4096, 16, 8192);
  auto memory = args->number("memory-mb", 1024.0, 0.0, 1e7);
  auto idle = args->integer("session-idle-s", 120, 1, 86400 * 7);
  for (const auto* r :
       {&port, &workers, &runners, &sessions, &queue, &streams, &jobs, &frames, &size, &idle})
    if (!*r) {
      std::fprintf(stderr, "hlodr serve: %s\n", r->message().c_str());
      return 2;
    }
  if (!memory) {
    std::fprintf(stderr, "hlodr serve: %s\n", memory.message().c_str());
    return 2;
  }
  o.port = int(*port);
  o.bind = args->get("bind", "127.0.0.1");
  o.dataDir = args->get("data", "hlodr-data");
  o.workers = int(*workers);
  o.jobRunners = int(*runners);
  o.maxSessions = std::size_t(*sessions);
  o.queue = std::size_t(*queue);
  o.maxStreams = std::size_t(*streams);
  o.maxJobs = std::size_t(*jobs);
  o.maxFrames = std::uint64_t(*frames);
  o.maxSize = int(*size);
  o.cacheBytes = std::uint64_t(*memory * 1024.0 * 1024.0);
  o.sessionIdleSeconds = int(*idle);
  o.accessLog = !args->has("quiet");
  o.jobsDir = args->get("jobs-dir", "");
  o.webDir = args->has("web") ? fs::path(args->get("web", "")) : findWebDir();
  std::error_code ec;
  if (args->has("web") && !fs::exists(o.webDir / "index.html", ec)) {
    std::fprintf(stderr, "hlodr serve: --web %s holds no index.html\n", o.webDir.c_str());
    return 2;
  }
  auto backend = renderer::backendFromEnvironment();
  if (!backend) {
    std::fprintf(stderr, "hlodr serve: %s\n", backend.message().c_str());
    return 2;
  }
  o.backend = *backend;

  // SIGINT and SIGTERM are taken by a thread of their own (sigwait), blocked everywhere else:
  // set before any thread starts, so every thread inherits the mask.
  sigset_t stopSignals;
  sigemptyset(&stopSignals);
  sigaddset(&stopSignals, SIGINT);
  sigaddset(&stopSignals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stopSignals, nullptr);

  fs::create_directories(o.dataDir, ec);
  if (!fs::is_directory(o.dataDir, ec)) {
    std::fprintf(stderr, "hlodr serve: cannot create the data folder %s\n", o.dataDir.c_str());
    return 1;
  }
  if (!hasStore(o.dataDir)) {
    if (auto s = makeDefaultCity(o.dataDir); !s) {
      std::fprintf(stderr, "hlodr serve: the default city: %s\n", s.message().c_str());
      return 1;
    }
  }
  if (o.webDir.empty()) logLine("no web page found (set --web DIR): serving the API only");
  auto server = Server::create(o, logLine);
  if (!server) {
    std::fprintf(stderr, "hlodr serve: %s\n", server.message().c_str());
    return 1;
  }
  auto bound = (*server)->bind();
  if (!bound) {
    std::fprintf(stderr, "hlodr serve: %s\n", bound.message().c_str());
    return 1;
  }
  std::thread signals([&] {
    int sig = 0;
    sigwait(&stopSignals, &sig);
    if (sig == 0) return;
    logLine(std::string("stopping (") + (sig == SIGINT ? "SIGINT" : "SIGTERM") + ")");
    (*server)->stop();
  });
  logLine("hlodr serve: listening on " + (*server)->url());
  std::printf("hlodr is serving %s at %s\n", o.dataDir.c_str(), (*server)->url().c_str());
  std::fflush(stdout);
  (*server)->run();
  // The signal thread may still wait: wake it with a signal of its own set.
  if (signals.joinable()) {
    pthread_kill(signals.native_handle(), SIGTERM);
    signals.join();
  }
  return 0;
}

}  // namespace service::cmd
