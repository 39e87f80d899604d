// Occlusion culling (Manocha sec. 4.1-4.3 and 6.2; hlod/runtime/OcclusionCulling.h) on a store's
// paths, settled at 30 fps, with culling on and off:
//  - culling efficiency as Manocha sec. 6.2 defines it: primitives in the potentially visible
//    set (the triangles drawn) over primitives actually visible (an ID-buffer render of the same
//    front, renderer/IdBuffer.h); per phase of the walk-fly (street 0-15 s, rise 15-30 s,
//    fly-over 30 s on), with culling and with the frustum alone;
//  - popping: the pixels that differ between the frame drawn with culling and the same front
//    drawn with the nodes culled from it added back (late query answers), median and worst
//    frame, on the walk-fly and on a path with a fast turn (90 degrees in 0.5 s) and a step out
//    from behind a corner;
//  - the frame's time with and without culling, the occlusion pass's ms and the queries.
//
// Run: ./occlusion_bench [STORE] [--frames N] [--budget-ms MS] [--size WxH]
// Without STORE the default city is generated and built under ./walk_bench_data (once).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "BenchCity.h"
#include "hlod/runtime/CameraPath.h"
#include "hlod/store/NodeStore.h"
#include "service/Session.h"

namespace {

struct Phase {
  const char* name;
  double from, to;
  double pvs = 0.0, visible = 0.0, frustumPvs = 0.0, frustumVisible = 0.0;
  double drawnOn = 0.0, drawnOff = 0.0, visibleNodeTrisOn = 0.0, visibleNodeTrisOff = 0.0;
  double msOn = 0.0, msOff = 0.0, occlusionMs = 0.0, queries = 0.0;
  int frames = 0;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double differingShare(const hlod::Image& a, const hlod::Image& b) {
  if (a.pixels.size() != b.pixels.size() || a.pixels.empty()) return 1.0;
  std::size_t d = 0;
  for (std::size_t i = 0; i < a.pixels.size(); i += 4)
    d += a.pixels[i] != b.pixels[i] || a.pixels[i + 1] != b.pixels[i + 1] ||
         a.pixels[i + 2] != b.pixels[i + 2];
  return double(d) / double(a.pixels.size() / 4);
}

// A street walk with a fast turn and a step out from behind a corner: along the street nearest
// the model's centre for 4 s, a 90 degree turn in 0.5 s, on for 3 s, then a sideways step of
// 6 m in 1 s past the block's corner, and on.
hlod::Result<hlod::CameraPath> turnAndCornerPath(const hlod::Skeleton& sk) {
  auto walk = hlod::makeWalkFlyPath(sk);
  if (!walk) return walk.error();
  const hlod::CameraSample s0 = walk->sample(0.0, 1.0);
  const glm::dvec3 p0 = s0.camera.position;
  const glm::dvec3 ahead = glm::normalize(s0.camera.target - p0);
  const glm::dvec3 side = glm::normalize(glm::cross(ahead, glm::dvec3(0, 0, 1)));
  std::vector<hlod::CameraKeyframe> k;
  auto key = [&](double t, glm::dvec3 p, glm::dvec3 dir) {
    hlod::CameraKeyframe f;
    f.time = t;
    f.position = p;
    f.target = p + 30.0 * dir;
    k.push_back(f);
  };
  const double v = 2.0;
  const glm::dvec3 p1 = p0 + ahead * (v * 4.0);
  key(0.0, p0, ahead);
  key(4.0, p1, ahead);
  key(4.25, p1, glm::normalize(ahead + side));
  key(4.5, p1, side);
  const glm::dvec3 p2 = p1 + side * (v * 3.0);
  key(7.5, p2, side);
  key(8.5, p2 + ahead * 6.0, side);
  key(11.0, p2 + ahead * 6.0 + side * (v * 2.5), side);
  return hlod::CameraPath::fromKeyframes(std::move(k));
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path store;
  long long maxFrames = -1;
  double budgetMs = 33.0;
  int width = 1280, height = 720;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--frames" && i + 1 < argc) {
      maxFrames = std::atoll(argv[++i]);
    } else if (a == "--budget-ms" && i + 1 < argc) {
      budgetMs = std::atof(argv[++i]);
    } else if (a == "--size" && i + 1 < argc) {
      if (std::sscanf(argv[++i], "%dx%d", &width, &height) != 2) return 2;
    } else if (a.rfind("--", 0) == 0) {
      std::fprintf(stderr,
                   "usage: occlusion_bench [STORE] [--frames N] [--budget-ms MS] "
                   "[--size WxH] [--part culling|loading|prediction|all]\n");
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
  const hlod::Skeleton& sk = (*opened)->skeleton();
  auto walkFly = hlod::makeWalkFlyPath(sk);
  auto turn = turnAndCornerPath(sk);
  if (!walkFly || !turn) {
    std::fprintf(stderr, "paths: %s\n", (!walkFly ? walkFly : turn).message().c_str());
    return 1;
  }

  service::SessionOptions base;
  base.width = width;
  base.height = height;
  base.budgetMs = budgetMs;
  base.recentFrames = 0;
  std::printf("store %s, %dx%d, lakhia %.0f ms, settled at 30 fps\n", store.c_str(), width, height,
              budgetMs);
  for (int which = 0; which < 2; ++which) {
    const hlod::CameraPath& path = which == 0 ? *walkFly : *turn;
    std::vector<Phase> phases =
        which == 0 ? std::vector<Phase>{{"street", 0, 15}, {"rise", 15, 30}, {"fly-over", 30, 1e9}}
                   : std::vector<Phase>{{"turn+corner", 0, 1e9}};
    service::SessionOptions on = base, off = base;
    on.occlusion = hlod::OcclusionMode::On;
    off.occlusion = hlod::OcclusionMode::Off;
    auto a = service::Session::open(store, on);
    auto b = service::Session::open(store, off);
    if (!a || !b) {
      std::fprintf(stderr, "%s\n", (!a ? a.message() : b.message()).c_str());
      return 1;
    }
    const double fps = 30.0;
    auto count = path.frameCount(fps, maxFrames > 0 ? std::uint64_t(maxFrames) : 100000);
    if (!count) return 1;
    std::vector<double> popping;
    for (std::uint64_t f = 0; f < *count; ++f) {
      const hlod::CameraSample s = path.sampleFrame(f, fps, double(width) / height);
      auto ra = (*a)->renderFrame(s, hlod::FrameMode::Settled);
      if (!ra) {
        std::fprintf(stderr, "%s\n", ra.message().c_str());
        return 1;
      }
      const hlod::Image culled = (*a)->readback();
      const std::vector<std::uint32_t> front = (*a)->driver().lastFront();
      const std::vector<hlod::NodeDraw> draws = (*a)->driver().lastDraws();
      auto visibleOn = (*a)->gpu().countVisible(s.camera, front, draws);
      // The same front with what culling left out added back, drawn without queries.
      std::vector<std::uint32_t> all = front;
      std::vector<hlod::NodeDraw> allDraws = draws;
      for (std::uint32_t n : (*a)->driver().lastOccluded()) {
        all.push_back(n);
        allDraws.push_back({sk.nodes[n].numTri, false});
      }
      hlod::orderNearToFar(sk, s.camera.position, all, allDraws);
      auto full = (*a)->gpu().draw(s.camera, all, allDraws, nullptr);
      if (!full || !visibleOn) return 1;
      popping.push_back(differingShare(culled, (*a)->gpu().readback()));

      auto rb = (*b)->renderFrame(s, hlod::FrameMode::Settled);
      if (!rb) return 1;
      auto visibleOff = (*b)->gpu().countVisible(s.camera, (*b)->driver().lastFront(),
                                                 (*b)->driver().lastDraws());
      if (!visibleOff) return 1;
      for (Phase& p : phases) {
        if (s.time < p.from || s.time >= p.to) continue;
        ++p.frames;
        p.pvs += double(ra->triangles);
        p.visible += double(visibleOn->primitives);
        p.frustumPvs += double(rb->triangles);
        p.frustumVisible += double(visibleOff->primitives);
        p.visibleNodeTrisOn += double(visibleOn->meshTriangles);
        p.visibleNodeTrisOff += double(visibleOff->meshTriangles);
        p.drawnOn += double(ra->triangles);
        p.drawnOff += double(rb->triangles);
        p.msOn += ra->gpuMs;
        p.msOff += rb->gpuMs;
        p.occlusionMs += ra->occlusionMs;
        p.queries += ra->occlusionQueries;
      }
    }
    std::printf("\n%s: %llu frames\n", which == 0 ? "walk-fly" : "turn and corner",
                (unsigned long long)*count);
    std::printf("%-12s %6s %9s %9s %9s %9s %8s %8s %7s %7s\n", "phase", "frames", "eff on",
                "eff off", "tri on", "tri off", "ms on", "ms off", "occ ms", "queries");
    for (const Phase& p : phases) {
      if (p.frames == 0) continue;
      const double n = p.frames;
      std::printf("%-12s %6d %9.2f %9.2f %8.0fk %8.0fk %8.1f %8.1f %7.2f %7.0f\n", p.name, p.frames,
                  p.visible > 0 ? p.pvs / p.visible : 0.0,
                  p.frustumVisible > 0 ? p.frustumPvs / p.frustumVisible : 0.0, p.drawnOn / n / 1e3,
                  p.drawnOff / n / 1e3, p.msOn / n, p.msOff / n, p.occlusionMs / n, p.queries / n);
      std::printf(
          "%-12s triangles drawn on visible nodes: on %.0fk, off %.0fk (of %.0fk, "
          "%.0fk drawn)\n",
          "", p.visibleNodeTrisOn / n / 1e3, p.visibleNodeTrisOff / n / 1e3, p.drawnOn / n / 1e3,
          p.drawnOff / n / 1e3);
    }
    std::printf(
        "popping (pixels differing from the same front unculled): median %.4f%%, worst "
        "%.4f%%\n",
        100.0 * median(popping),
        100.0 * (popping.empty() ? 0.0 : *std::max_element(popping.begin(), popping.end())));
    std::fflush(stdout);
  }
  return 0;
}
