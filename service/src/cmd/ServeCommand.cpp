// `hlodr serve`: the HTTP service and its page over the node stores of a data folder.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
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
#include "service/Settings.h"

namespace service::cmd {

namespace fs = std::filesystem;

const char* const kServeUsage =
    "usage: hlodr serve [--port 8080] [--bind 127.0.0.1] [--data DIR] [options]\n"
    "\n"
    "Serves the HTTP API (docs/api.md) and the web page over the node stores in DIR (each\n"
    "NAME.hlod/ folder is scene NAME). When DIR holds no store, it generates the default city\n"
    "(DIR/city/) and builds its store (DIR/city.hlod/) first, once. Open the printed URL.\n"
    "SIGINT or SIGTERM stop it gracefully (after --drain-s): running jobs are cancelled and\n"
    "close their files.\n"
    "Jobs keep their records and outputs in the jobs folder and are listed again after a\n"
    "restart; finished ones expire by --keep-jobs-days and --jobs-max-mb.\n"
    "\n"
    "options:\n"
    "{serve.port}\n"
    "{serve.bind}\n"
    "{serve.data}\n"
    "{serve.workers}\n"
    "{serve.jobRunners}\n"
    "{serve.maxSessions}\n"
    "{serve.admission}\n"
    "{serve.queue}\n"
    "{serve.maxStreams}\n"
    "{serve.maxJobs}\n"
    "{serve.maxFrames}\n"
    "{serve.maxSize}\n"
    "{serve.memoryMb}\n"
    "{serve.glMemoryMb}\n"
    "{serve.sessionIdleS}\n"
    "{serve.requestTimeoutS}\n"
    "{serve.maxConnectionsPerAddress}\n"
    "{serve.drainS}\n"
    "{serve.keepJobsDays}\n"
    "{serve.jobsMaxMb}\n"
    "{serve.web}\n"
    "{serve.jobsDir}\n"
    "  --quiet                 no access log\n"
    "\n"
    "environment: HLODR_GL_BACKEND=egl|osmesa forces a GL backend; HLODR_DATA is the default\n"
    "data folder.\n";

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
  const std::vector<std::string> ids = {"serve.port",
                                        "serve.bind",
                                        "serve.data",
                                        "serve.workers",
                                        "serve.jobRunners",
                                        "serve.maxSessions",
                                        "serve.admission",
                                        "serve.queue",
                                        "serve.maxStreams",
                                        "serve.maxJobs",
                                        "serve.maxFrames",
                                        "serve.maxSize",
                                        "serve.memoryMb",
                                        "serve.glMemoryMb",
                                        "serve.sessionIdleS",
                                        "serve.requestTimeoutS",
                                        "serve.maxConnectionsPerAddress",
                                        "serve.drainS",
                                        "serve.keepJobsDays",
                                        "serve.jobsMaxMb",
                                        "serve.web",
                                        "serve.jobsDir"};
  std::set<std::string> options;
  for (const auto& id : ids) options.insert(settings::get(id).cli);
  auto args = Args::parse(argv, {"quiet"}, options);
  if (!args) {
    std::fprintf(stderr, "hlodr serve: %s\n%s", args.message().c_str(),
                 expandUsage(kServeUsage).c_str());
    return 2;
  }
  if (!args->positionals().empty()) {
    std::fprintf(stderr, "hlodr serve: unexpected argument '%s' (the data folder is --data DIR)\n",
                 args->positionals()[0].c_str());
    return 2;
  }
  using settings::get;
  ServerOptions o;
  auto port = args->integer(get("serve.port"));
  auto workers = args->integer(get("serve.workers"));
  auto runners = args->integer(get("serve.jobRunners"));
  auto sessions = args->integer(get("serve.maxSessions"));
  auto queue = args->integer(get("serve.queue"));
  auto streams = args->integer(get("serve.maxStreams"));
  auto jobs = args->integer(get("serve.maxJobs"));
  auto frames = args->integer(get("serve.maxFrames"));
  auto size = args->integer(get("serve.maxSize"));
  auto idle = args->integer(get("serve.sessionIdleS"));
  auto timeout = args->integer(get("serve.requestTimeoutS"));
  auto perAddress = args->integer(get("serve.maxConnectionsPerAddress"));
  auto drainS = args->integer(get("serve.drainS"));
  for (const auto* r : {&port, &workers, &runners, &sessions, &queue, &streams, &jobs, &frames,
                        &size, &idle, &timeout, &perAddress, &drainS})
    if (!*r) return usageError("serve", r->message());
  auto admission = args->choice(get("serve.admission"));
  if (!admission) return usageError("serve", admission.message());
  auto memory = args->number(get("serve.memoryMb"));
  auto glMemory = args->number(get("serve.glMemoryMb"));
  auto keepDays = args->number(get("serve.keepJobsDays"));
  auto jobsMb = args->number(get("serve.jobsMaxMb"));
  for (const auto* r : {&memory, &glMemory, &keepDays, &jobsMb})
    if (!*r) return usageError("serve", r->message());
  o.port = int(*port);
  o.bind = args->get("bind", get("serve.bind").fallback);
  // The container image sets HLODR_DATA=/data: `hlodr serve` needs no --data there.
  const char* dataEnv = std::getenv("HLODR_DATA");
  o.dataDir = args->get("data", dataEnv && *dataEnv ? dataEnv : get("serve.data").fallback);
  o.workers = int(*workers);
  o.jobRunners = int(*runners);
  o.maxSessions = std::size_t(*sessions);
  o.shareBudget = *admission == "share";
  o.queue = std::size_t(*queue);
  o.maxStreams = std::size_t(*streams);
  o.maxJobs = std::size_t(*jobs);
  o.maxFrames = std::uint64_t(*frames);
  o.maxSize = int(*size);
  o.cacheBytes = std::uint64_t(*memory * 1048576.0);
  o.glMemoryBytes = std::uint64_t(*glMemory * 1048576.0);
  o.sessionIdleSeconds = int(*idle);
  o.requestTimeoutSeconds = int(*timeout);
  o.maxConnectionsPerAddress = std::size_t(*perAddress);
  o.keepJobsDays = *keepDays;
  o.jobsMaxBytes = std::uint64_t(*jobsMb * 1048576.0);
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
  std::atomic<bool> served{false};  // run() returned: the wake-up below is no stop request
  std::thread signals([&] {
    int sig = 0;
    sigwait(&stopSignals, &sig);
    if (sig == 0 || served) return;
    const std::string name = sig == SIGINT ? "SIGINT" : "SIGTERM";
    if (*drainS > 0) {
      // Drain first: /healthz says 503 so the load balancer sends new sessions elsewhere, while
      // the current ones keep their frames; a second signal cuts it short.
      (*server)->drain();
      logLine("draining for " + std::to_string(*drainS) + " s (" + name + ")");
      const timespec wait{static_cast<time_t>(*drainS), 0};
      sigtimedwait(&stopSignals, nullptr, &wait);
    }
    logLine("stopping (" + name + ")");
    (*server)->stop();
  });
  logLine("hlodr serve: listening on " + (*server)->url());
  std::printf("hlodr is serving %s at %s\n", o.dataDir.c_str(), (*server)->url().c_str());
  std::fflush(stdout);
  (*server)->run();
  // The signal thread may still wait: wake it with a signal of its own set.
  served = true;
  if (signals.joinable()) {
    pthread_kill(signals.native_handle(), SIGTERM);
    signals.join();
  }
  return 0;
}

}  // namespace service::cmd
