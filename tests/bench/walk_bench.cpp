// Lakhia IV on the default city: the walk-to-fly path at 1280x720, 33 ms budget, realtime mode,
// with the Lakhia selector and with the SSE selector tuned (bisection on its pixel threshold) to
// the same mean frame time; each unthrottled and behind an emulated 50 Mbit/s, 5 ms link (4
// requests in flight, --io-requests); and
// Lakhia with the known-path prefetch (1 s ahead). Prints per run: median and p95 of
// |actual - target| / target, share of frames over target and over 1.25x, p99 of actual /
// target, stalls, peak resident bytes / cap, toggles per frame, triangles drawn per frame and
// nodes per frame drawn coarser because their children were not loaded yet.
//
// Run: ./walk_bench [STORE] [--frames N] [--memory-mb M] [--plots DIR] [--lakhia-only]
//                   [--no-prefetch] [--unthrottled-only | --throttled-only]
//                   [--params NAME=VALUE,...] [--io-requests N] [--kind K | --path PATH.json]
// --kind K: another generated path (`hlodr path --kind`: catwalk for the power plant), --path
// a path file, instead of the walk-fly.
// --plots DIR keeps each run's stats.json/csv and the three plots in DIR/RUN/.
// Without STORE the default city is generated and built under ./walk_bench_data (once).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>

#include "BenchCity.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/city/City.h"
#include "hlod/store/NodeStore.h"
#include "service/Session.h"

namespace {

struct Run {
  std::string name;
  hlod::FrameSummary s;
  double ssePixels = 0.0;
};

hlod::Result<hlod::FrameSummary> runOnce(const std::filesystem::path& store,
                                         const hlod::CameraPath& path, service::SessionOptions o,
                                         long long frames, const std::filesystem::path& plots,
                                         const std::string& prefix, double prefetchSeconds = 0.0) {
  auto session = service::Session::open(store, o);
  if (!session) return session.error();
  hlod::PathRunOptions r;
  r.maxFrames = frames;
  r.prefetchSeconds = prefetchSeconds;
  service::FileOutputs fo;
  fo.statsDir =
      (plots.empty() ? std::filesystem::temp_directory_path() / "walk_bench_stats" : plots) /
      (prefix.empty() ? "sse_tuning" : prefix);
  fo.plots = !plots.empty() && !prefix.empty();
  std::filesystem::create_directories(fo.statsDir);
  auto result = service::runPathToFiles(**session, path, r, fo);
  if (!result) return result.error();
  return result->summary;
}

void print(const Run& r) {
  const auto& s = r.s;
  std::printf("%-30s %6.1f %7.3f %7.3f %6.1f%% %6.1f%% %7.2f %6llu %7.2f %7.2f %6.0fk %7.2f\n",
              r.name.c_str(), s.meanGpuMs, s.medianRelError, s.p95RelError,
              100.0 * s.shareOverTarget, 100.0 * s.shareOver125, s.p99OverTarget,
              (unsigned long long)s.totalStalls, s.peakOverCap, s.togglesPerFrame,
              s.meanTriangles / 1000.0, s.coarserPerFrame);
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path store;
  long long frames = -1;
  double memoryMb = 256.0;
  bool sse = true;
  bool prefetch = true;
  std::string first = "lakhia";
  int ioFirst = 0, ioLast = 1;
  std::filesystem::path plots;
  std::size_t ioRequests = 4;   // requests in flight on the throttled link
  hlod::SelectorParams params;  // --params: the selector constants (see hlodr render --params)
  std::string kind = "walk-fly", pathFile;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--frames" && i + 1 < argc) {
      frames = std::atoll(argv[++i]);
    } else if (a == "--memory-mb" && i + 1 < argc) {
      memoryMb = std::atof(argv[++i]);
    } else if (a == "--selector" && i + 1 < argc) {
      first = argv[++i];
    } else if (a == "--lakhia-only") {
      sse = false;
    } else if (a == "--no-prefetch") {
      prefetch = false;
    } else if (a == "--unthrottled-only") {
      ioLast = 0;
    } else if (a == "--throttled-only") {
      ioFirst = 1;
    } else if (a == "--plots" && i + 1 < argc) {
      plots = argv[++i];
    } else if (a == "--io-requests" && i + 1 < argc) {
      ioRequests = static_cast<std::size_t>(std::max(1LL, std::atoll(argv[++i])));
    } else if (a == "--params" && i + 1 < argc) {
      if (auto p = hlod::setSelectorParams(params, argv[++i]); !p) {
        std::fprintf(stderr, "walk_bench: %s\n", p.message().c_str());
        return 2;
      }
    } else if (a == "--kind" && i + 1 < argc) {
      kind = argv[++i];
    } else if (a == "--path" && i + 1 < argc) {
      pathFile = argv[++i];
    } else if (a.rfind("--", 0) == 0) {
      std::fprintf(stderr,
                   "usage: walk_bench [STORE] [--frames N] [--memory-mb M] [--plots DIR]\n"
                   "                  [--lakhia-only] [--no-prefetch]\n"
                   "                  [--unthrottled-only | --throttled-only]\n"
                   "                  [--params NAME=VALUE,...] [--io-requests N]\n"
                   "                  [--kind K | --path PATH.json]\n");
      return 2;
    } else {
      store = a;
    }
  }
  auto made = bench::storeOrDefaultCity(store, "walk_bench_data");
  if (!made) {
    std::fprintf(stderr, "%s\n", made.message().c_str());
    return 1;
  }
  store = *made;
  auto skeleton = hlod::NodeStore::open(store);
  if (!skeleton) {
    std::fprintf(stderr, "%s\n", skeleton.message().c_str());
    return 1;
  }
  auto path =
      pathFile.empty() ? hlod::makeCameraPath(kind, **skeleton) : hlod::CameraPath::read(pathFile);
  if (!path) {
    std::fprintf(stderr, "%s\n", path.message().c_str());
    return 1;
  }

  service::SessionOptions base;
  base.width = 1280;
  base.height = 720;
  base.budgetMs = 33.0;
  base.memoryCapBytes = std::uint64_t(memoryMb * 1024 * 1024);
  base.selectorParams = params;
  std::printf("%s %.1f s at 30 fps, 1280x720, budget 33 ms, realtime, cap %.0f MB\n",
              pathFile.empty() ? kind.c_str() : pathFile.c_str(), path->duration(), memoryMb);
  std::printf("%-30s %6s %7s %7s %7s %7s %7s %6s %7s %7s %7s %7s\n", "run", "mean", "med|d|",
              "p95|d|", ">tgt", ">1.25x", "p99/t", "stalls", "pk/cap", "tog/fr", "tri/fr",
              "crs/fr");
  for (int io = ioFirst; io <= ioLast; ++io) {
    service::SessionOptions o = base;
    if (io) o.ioMbps = 50.0, o.ioLatencyMs = 5.0, o.ioRequests = ioRequests;
    const std::string link = io ? ", 50 Mbit/s 5 ms" : ", unthrottled";
    o.selector = first;
    // One run of the chosen selector, printed as it ends.
    auto measure = [&](const std::string& name, const std::string& prefix,
                       double prefetchSeconds) -> std::optional<Run> {
      auto r = runOnce(store, *path, o, frames, plots, prefix + (io ? "_io" : ""), prefetchSeconds);
      if (!r) {
        std::fprintf(stderr, "%s\n", r.message().c_str());
        return std::nullopt;
      }
      Run run{name + link, *r};
      print(run);
      std::fflush(stdout);
      return run;
    };
    const auto lakhia = measure(first, "lakhia", 0.0);
    if (!lakhia) return 1;
    if (prefetch && !measure(first + " + prefetch", "prefetch", 1.0)) return 1;
    if (!sse) continue;
    // SSE tuned to Lakhia's mean frame time: bisection on log(pixels), larger = coarser.
    o.selector = "sse";
    double lo = std::log(0.25), hi = std::log(256.0);
    Run best;
    double bestGap = 1e300;
    for (int it = 0; it < 6; ++it) {
      const double mid = 0.5 * (lo + hi);
      o.selectorParams.ssePixels = std::exp(mid);
      auto r = runOnce(store, *path, o, frames, {}, "");
      if (!r) {
        std::fprintf(stderr, "%s\n", r.message().c_str());
        return 1;
      }
      const double gap = std::abs(r->meanGpuMs - lakhia->s.meanGpuMs);
      std::fprintf(stderr, "  sse %.2f px: mean %.1f ms (lakhia %.1f)\n", std::exp(mid),
                   r->meanGpuMs, lakhia->s.meanGpuMs);
      if (gap < bestGap) bestGap = gap, best.s = *r, best.ssePixels = std::exp(mid);
      if (r->meanGpuMs > lakhia->s.meanGpuMs)
        lo = mid;
      else
        hi = mid;
    }
    char name[64];
    std::snprintf(name, sizeof name, "sse %.1f px%s", best.ssePixels, link.c_str());
    best.name = name;
    print(best);
    std::fflush(stdout);
  }
  return 0;
}
