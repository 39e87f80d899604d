// The cold start (issue 13): a new session's first settled frame at a budget, on the default
// city, from a few cameras: with the v_time its start measures (the calibration draw of hlod_0),
// and with the v_time a previous session of the same server left (what `hlodr serve` passes on).
// Before, the first frame started at v_time 1e-5 and selected every leaf (560 ms at 33 ms).
//   coldstart_bench [STORE] [--budget-ms 33] [--size 640x360] [--repeat 3]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "BenchCity.h"
#include "hlod/runtime/CameraPath.h"
#include "hlod/store/NodeStore.h"
#include "service/SceneLoading.h"
#include "service/Session.h"

int main(int argc, char** argv) {
  std::filesystem::path store;
  double budget = 33.0;
  int width = 640, height = 360, repeat = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--budget-ms" && i + 1 < argc) {
      budget = std::atof(argv[++i]);
    } else if (a == "--size" && i + 1 < argc) {
      std::sscanf(argv[++i], "%dx%d", &width, &height);
    } else if (a == "--repeat" && i + 1 < argc) {
      repeat = std::max(1, std::atoi(argv[++i]));
    } else if (a.rfind("--", 0) == 0) {
      std::fprintf(stderr,
                   "usage: coldstart_bench [STORE] [--budget-ms MS] [--size WxH] [--repeat N]\n");
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
  auto opened = hlod::NodeStore::open(store);
  if (!opened) {
    std::fprintf(stderr, "%s\n", opened.message().c_str());
    return 1;
  }
  std::shared_ptr<const hlod::NodeSource> source(std::move(*opened));
  const hlod::Skeleton& sk = source->skeleton();
  hlod::Aabb bounds;
  for (auto r : sk.roots) bounds.extend(sk.nodes[r].bounds);
  const double aspect = double(width) / height;

  struct View {
    const char* name;
    hlod::CameraSample sample;
  };
  std::vector<View> views;
  {
    const auto pose = service::defaultCamera(bounds, sk.up, 50.0, aspect);
    hlod::CameraSample s;
    s.camera.position = pose.position;
    s.camera.target = pose.target;
    s.camera.fovY = pose.fovY;
    views.push_back({"default view", s});
  }
  if (auto walk = hlod::makeWalkFlyPath(sk)) {
    views.push_back({"street (walk-fly t=2 s)", walk->sample(walk->startTime() + 2.0, aspect)});
    views.push_back({"fly-over (walk-fly t=32 s)", walk->sample(walk->startTime() + 32.0, aspect)});
  }
  {
    hlod::CameraSample s;
    s.camera.position = {550.7, 304.4, 713.6};
    s.camera.target = {393.4, 365.3, 0.0};
    views.push_back({"issue 13's fly-over camera", s});
  }

  std::printf("first settled frame of a new session, %dx%d, budget %.0f ms, %d runs each\n", width,
              height, budget, repeat);
  std::printf("%-30s %12s %8s %12s %9s %14s %8s\n", "camera", "measured: ms", "x budget",
              "triangles", "again ms", "known v: ms", "x budget");
  hlod::FrontTiming known;
  std::vector<double> ratios[2];  // first frame / budget: measured v_time, known v_time
  for (const View& v : views) {
    for (int r = 0; r < repeat; ++r) {
      double ms[2] = {0, 0}, tri = 0, againMs = 0;
      for (int pass = 0; pass < 2; ++pass) {
        service::SessionOptions o;
        o.width = width;
        o.height = height;
        o.budgetMs = budget;
        o.knownVTime = pass == 0 ? 0.0 : known.vTime;  // second: from the session before
        o.knownFixedMs = pass == 0 ? 0.0 : known.fixedMs;
        auto s = service::Session::create(source, o);
        if (!s) {
          std::fprintf(stderr, "%s\n", s.message().c_str());
          return 1;
        }
        auto rec = (*s)->renderFrame(v.sample, hlod::FrameMode::Settled);
        if (!rec) {
          std::fprintf(stderr, "%s\n", rec.message().c_str());
          return 1;
        }
        ms[pass] = rec->gpuMs;
        if (pass == 0) {
          tri = double(rec->triangles);
          // The same front drawn again (median of 3): what it costs once its first use is paid.
          // first/again apart from again/budget tells first-use costs from a wrong v_time.
          hlod::Camera cam = v.sample.camera;
          cam.aspect = aspect;
          const std::vector<std::uint32_t> front = (*s)->driver().lastFront();
          std::vector<double> again;
          for (int k = 0; k < 3; ++k) {
            auto next = (*s)->driver().renderer().draw(cam, front, (*s)->driver().lastDraws());
            if (!next) {
              std::fprintf(stderr, "%s\n", next.message().c_str());
              return 1;
            }
            again.push_back(next->ms);
          }
          std::sort(again.begin(), again.end());
          againMs = again[1];
        }
        known = (*s)->driver().timing();
        if (pass == 0 && r == 0 && &v == &views.front())
          std::fprintf(stderr, "(measured v_time %.3g ms per cost unit)\n",
                       (*s)->driver().measuredVTime());
      }
      std::printf("%-30s %12.1f %8.2f %12.0f %9.1f %14.1f %8.2f\n", r == 0 ? v.name : "", ms[0],
                  ms[0] / budget, tri, againMs, ms[1], ms[1] / budget);
      for (int pass = 0; pass < 2; ++pass) ratios[pass].push_back(ms[pass] / budget);
    }
  }
  // One frame's wall time is noisy on a shared machine: the median and the share within 1.25x
  // say more than the worst single frame.
  for (int pass = 0; pass < 2; ++pass) {
    auto& q = ratios[pass];
    std::sort(q.begin(), q.end());
    const auto within = std::count_if(q.begin(), q.end(), [](double x) { return x <= 1.25; });
    std::printf("%s v_time: median %.2f x budget, max %.2f, %ld of %zu first frames within 1.25x\n",
                pass == 0 ? "measured" : "known", q[q.size() / 2], q.back(), long(within),
                q.size());
  }
  return 0;
}
