// `hlodr path STORE --kind KIND -o PATH.json`: a camera path for a node store,
// and `hlodr render STORE --path PATH.json -o OUT`: a path run through a Session.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "cmd/Commands.h"
#include "cmd/SceneArgs.h"
#include "cmd/SessionArgs.h"
#include "hlod/runtime/CameraPath.h"
#include "hlod/runtime/Framing.h"
#include "hlod/runtime/Segments.h"
#include "hlod/store/NodeStore.h"
#include "service/Args.h"
#include "service/Progress.h"
#include "service/Session.h"
#include "service/Settings.h"

namespace service::cmd {

namespace fs = std::filesystem;

const char* const kPathUsage =
    "usage: hlodr path STORE --kind walk-fly|drive|orbit|facade|fly-around|catwalk -o PATH.json\n"
    "                  [--duration S]\n"
    "\n"
    "Writes a camera path (JSON keyframes: time, position, target, up, fov) for the model in the\n"
    "node STORE (made by `hlodr build`). Render it with `hlodr render STORE --path PATH.json`.\n"
    "\n"
    "options:\n"
    "{pathKind}\n"
    "  -o, --output PATH.json  output file (required)\n"
    "{duration}\n";

namespace {

bool isStore(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec) && fs::exists(p / "skeleton.bin", ec);
}

}  // namespace

bool isNodeStore(const std::string& path) {
  return isStore(path);
}

int runPath(const Argv& argv) {
  auto args = Args::parse(argv, {}, {"output", "kind", "duration"});
  if (!args) return usageError("path", args.message());
  const char* missing = args->positionals().size() != 1 ? "give one node STORE"
                        : !args->has("kind")            ? "--kind is required"
                        : !args->has("output")          ? "-o PATH.json is required"
                                                        : nullptr;
  if (missing) {
    std::fprintf(stderr, "hlodr path: %s\n%s", missing, expandUsage(kPathUsage).c_str());
    return 2;
  }
  auto duration = args->number(settings::get("duration"));
  if (!duration) return usageError("path", duration.message());
  auto kindChoice = args->choice(settings::get("pathKind"));
  if (!kindChoice) return usageError("path", kindChoice.message());
  const std::string kind = *kindChoice;

  const fs::path storePath = args->positionals()[0];
  if (!isStore(storePath)) {
    std::fprintf(stderr,
                 "hlodr path: %s is not a node store (a folder with skeleton.bin; make one with "
                 "`hlodr build`)\n",
                 storePath.string().c_str());
    return 1;
  }
  auto store = hlod::NodeStore::open(storePath);
  if (!store) {
    std::fprintf(stderr, "hlodr path: %s: %s\n", storePath.string().c_str(),
                 store.message().c_str());
    return 1;
  }
  auto path = hlod::makeCameraPath(kind, **store);
  if (!path) {
    std::fprintf(stderr, "hlodr path: %s\n", path.message().c_str());
    return 1;
  }
  if (args->has("duration")) {
    auto scaled = hlod::withDuration(*path, *duration);
    if (!scaled) {
      std::fprintf(stderr, "hlodr path: %s\n", scaled.message().c_str());
      return 1;
    }
    path = std::move(scaled);
  }
  const std::string out = args->get("output", "");
  if (auto w = path->write(out); !w) {
    std::fprintf(stderr, "hlodr path: %s\n", w.message().c_str());
    return 1;
  }
  std::printf("%s: %s path, %zu keyframes, %.1f s\n", out.c_str(), kind.c_str(),
              path->keyframes().size(), path->duration());
  return 0;
}

const std::set<std::string> kPathRunOptions = {
    "budget-ms",     "selector", "mode",      "memory-mb", "fps",         "io-mbps",
    "io-latency-ms", "frames",   "upload-ms", "params",    "io-requests", "splats",
    "occlusion",     "gpu-mb",   "segment",   "warmup"};
const std::set<std::string> kPathRunFlags = {"prefetch", "plots", "show-occlusion"};

hlod::Result<Args> parseWithPathRun(const Argv& argv, std::set<std::string> flags,
                                    std::set<std::string> options) {
  flags.insert(kPathRunFlags.begin(), kPathRunFlags.end());
  options.insert(kPathRunOptions.begin(), kPathRunOptions.end());
  return Args::parse(argv, flags, options);
}

int runRenderPath(const Argv& argv) {
  auto args = parseWithPathRun(argv, {"quiet", "unlit", "no-textures", "fog"},
                               {"output", "path", "size", "scene", "trace"});
  if (!args) return usageError("render", args.message());
  auto declared = sceneFromArgs(*args, {0.0, 0.0, 1.0});
  if (!declared) return usageError("render", declared.message());
  std::string store = args->positionals().empty() ? "" : args->positionals()[0];
  if (store.empty() && declared->fromFile && !declared->scene.store.empty())
    store = (declared->file.parent_path() / declared->scene.store).string();
  if ((args->positionals().size() != 1 && store.empty()) || !args->has("output") ||
      !args->has("path")) {
    std::fprintf(stderr,
                 "hlodr render: a node store needs --path PATH.json (make one with `hlodr path`) "
                 "and -o OUT (a folder or a .mp4)\n");
    return 2;
  }
  using settings::get;
  auto session0 = sessionFromArgs(*args);
  if (!session0) return usageError("render", session0.message());
  SessionOptions so = *session0;
  auto fps = args->number(get("fps"));
  auto ioMbps = args->number(get("ioMbps"));
  auto ioLatency = args->number(get("ioLatencyMs"));
  auto frames = args->integer(get("frames"));
  auto ioRequests = args->integer(get("ioRequests"));
  auto uploadMs = args->number(get("uploadMs"));
  for (const auto* r : {&fps, &ioMbps, &ioLatency, &uploadMs})
    if (!*r) return usageError("render", r->message());
  for (const auto* r : {&frames, &ioRequests})
    if (!*r) return usageError("render", r->message());
  so.ioMbps = *ioMbps;
  so.ioLatencyMs = *ioLatency;
  so.ioRequests = static_cast<std::size_t>(*ioRequests);
  so.uploadBudgetMs = *uploadMs;
  auto mode = args->choice(get("mode"));
  if (!mode) return usageError("render", mode.message());
  // Checked before the store opens and the session starts (seconds on a large store).
  hlod::PathRunOptions segment;
  if (auto seg = args->get("segment")) {
    auto spec = hlod::parseSegment(*seg);
    if (!spec) return usageError("render", spec.message());
    segment.segmentIndex = spec->index;
    segment.segmentCount = spec->count;
  }
  auto warmup = args->integer(get("warmup"));
  if (!warmup) return usageError("render", warmup.message());
  if (args->has("warmup") && !args->has("segment"))
    return usageError("render", "--warmup is for a segment (--segment I/N)");
  segment.warmupFrames = static_cast<std::uint64_t>(*warmup);
  so.effects = declared->scene.effects;
  auto backend = renderer::backendFromEnvironment();
  if (!backend) return usageError("render", backend.message());

  auto path = hlod::CameraPath::read(args->get("path", ""));
  if (!path) {
    std::fprintf(stderr, "hlodr render: %s: %s\n", args->get("path", "").c_str(),
                 path.message().c_str());
    return 1;
  }
  if (segment.segmentCount > 1) {
    segment.fps = *fps;
    segment.maxFrames = args->has("frames") ? *frames : -1;
    auto total = hlod::runFrameCount(*path, segment);
    if (!total) return usageError("render", total.message());
    if (segment.segmentCount > *total)
      return usageError("render", "--segment: cannot split " + std::to_string(*total) +
                                      " frames into " + std::to_string(segment.segmentCount) +
                                      " segments");
  }
  if (!isStore(store))
    return usageError("render", store +
                                    " is not a node store (a folder with skeleton.bin; make "
                                    "one with `hlodr build`)");
  auto opened = hlod::NodeStore::open(store);
  if (!opened) {
    std::fprintf(stderr, "hlodr render: %s: %s\n", store.c_str(), opened.message().c_str());
    return 1;
  }
  // The default sun stands above the store's up axis, as for `hlodr render MODEL`.
  declared = sceneFromArgs(*args, hlod::modelUpFrame((*opened)->skeleton()).up);
  if (!declared) return usageError("render", declared.message());
  so.effects = declared->scene.effects;
  auto session =
      Session::create(std::shared_ptr<const hlod::NodeSource>(std::move(*opened)), so, *backend);
  if (!session) {
    std::fprintf(stderr, "hlodr render: %s\n", session.message().c_str());
    return 1;
  }
  const bool quiet = args->has("quiet");
  if (!quiet) std::fprintf(stderr, "%s\n", renderer::describe((*session)->contextInfo()).c_str());

  hlod::PathRunOptions ro;
  ro.fps = *fps;
  ro.maxFrames = args->has("frames") ? *frames : -1;
  ro.prefetchSeconds = args->has("prefetch") ? 1.0 : 0.0;
  ro.mode = *mode == "settled" ? hlod::FrameMode::Settled : hlod::FrameMode::Realtime;
  ro.segmentIndex = segment.segmentIndex;
  ro.segmentCount = segment.segmentCount;
  ro.warmupFrames = segment.warmupFrames;
  FileOutputs outputs;
  outputs.output = args->get("output", "");
  outputs.plots = args->has("plots");
  outputs.trace = args->get("trace", "");
  ProgressLine progress("render", quiet);
  auto result = runPathToFiles(
      **session, *path, ro, outputs,
      [&](const hlod::FrameRecord& rec, std::uint64_t done, std::uint64_t total) {
        char line[160];
        std::snprintf(line, sizeof line, "frame %llu/%llu  %6.1f ms (target %.0f)  %9llu triangles",
                      static_cast<unsigned long long>(done), static_cast<unsigned long long>(total),
                      rec.gpuMs, rec.targetMs, static_cast<unsigned long long>(rec.triangles));
        progress.update(static_cast<double>(done) / static_cast<double>(total), line);
      });
  progress.done();
  if (!result) {
    std::fprintf(stderr, "hlodr render: %s\n", result.message().c_str());
    return 1;
  }
  // A node that failed to load was drawn coarser all along: say so, and fail the run.
  const std::string failure = (*session)->loadFailure();
  if (!failure.empty()) std::fprintf(stderr, "hlodr render: %s\n", failure.c_str());
  const auto& s = result->summary;
  std::printf(
      "%zu frames -> %s\n"
      "frame time vs target %.1f ms: median |actual-target|/target %.3f, p95 %.3f, over target "
      "%.1f%%, over 1.25x %.1f%%, p99 actual/target %.2f, mean %.2f ms\n"
      "stalls %llu, toggles/frame %.2f, peak resident %.1f MB",
      static_cast<std::size_t>(result->run.framesRendered), outputs.output.string().c_str(),
      so.budgetMs, s.medianRelError, s.p95RelError, 100.0 * s.shareOverTarget,
      100.0 * s.shareOver125, s.p99OverTarget, s.meanGpuMs,
      static_cast<unsigned long long>(s.totalStalls), s.togglesPerFrame,
      s.peakResidentBytes / 1048576.0);
  if (s.capBytes > 0) std::printf(" of cap %.1f MB (%.2f)", s.capBytes / 1048576.0, s.peakOverCap);
  std::printf("\nstats: %s\n", result->statsJson.string().c_str());
  if (!outputs.trace.empty()) std::printf("trace: %s\n", outputs.trace.string().c_str());
  if (ro.segmentCount > 1)
    std::printf("segment %u/%u: frames %llu..%llu of %llu, after %llu warm-up frames\n",
                ro.segmentIndex, ro.segmentCount,
                static_cast<unsigned long long>(result->run.firstFrame),
                static_cast<unsigned long long>(result->run.endFrame - 1),
                static_cast<unsigned long long>(result->run.runFrames),
                static_cast<unsigned long long>(result->run.warmupFrames));
  for (const auto& p : result->plots) std::printf("plot: %s\n", p.string().c_str());
  return failure.empty() ? 0 : 1;
}

}  // namespace service::cmd
