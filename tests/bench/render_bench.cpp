// Full-detail rendering throughput at 1280x720: triangles per second on this machine's GL
// (llvmpipe here). The scene is the default procedural city, every block at full detail, seen
// from the default three-quarter view; and a single block close up (fill-bound rather than
// vertex-bound). Each also with glibc's default heap thresholds, as before renderer::keepFreedHeap
// (`_glibc_heap`), side by side. Run: build/tests/render_bench
#include <benchmark/benchmark.h>
#include <malloc.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <vector>

#include "hlod/city/City.h"
#include "renderer/GlContext.h"
#include "renderer/Renderer.h"
#include "service/SceneLoading.h"

namespace {

struct Scene {
  std::unique_ptr<renderer::GlContext> context;
  std::unique_ptr<renderer::Renderer> renderer;
  std::vector<renderer::GpuMesh> meshes;
  hlod::Aabb bounds;
};

Scene& city(int blocks) {
  static std::map<int, Scene> scenes;
  auto it = scenes.find(blocks);
  if (it != scenes.end()) return it->second;
  Scene& s = scenes[blocks];
  auto ctx = renderer::createContext(renderer::Backend::Auto);
  if (!ctx) {
    std::fprintf(stderr, "no GL: %s\n", ctx.message().c_str());
    std::exit(1);
  }
  s.context = std::move(*ctx);
  std::fprintf(stderr, "%s\n", renderer::describe(s.context->info()).c_str());
  renderer::RenderOptions options;  // 1280x720, textures + lambert
  s.renderer = std::move(*renderer::Renderer::create(*s.context, options));
  hlod::CityOptions co;
  co.blocks = blocks;
  for (int i = 0; i < blocks; ++i) {
    const auto block = hlod::generateBlock(co, i);
    s.bounds.extend(block.bounds());
    s.meshes.push_back(
        std::move(*renderer::GpuMesh::upload(s.context->gl(), hlod::toLocal(block))));
  }
  return s;
}

void renderCity(benchmark::State& state, int blocks, bool closeUp, bool glibcHeap = false) {
  Scene& s = city(blocks);
  s.context->makeCurrent();
  if (glibcHeap) {
    mallopt(M_MMAP_THRESHOLD, 128 * 1024);
    mallopt(M_TRIM_THRESHOLD, 128 * 1024);
  }
  std::vector<const renderer::GpuMesh*> list;
  std::uint64_t triangles = 0;
  for (const auto& m : s.meshes) {
    list.push_back(&m);
    triangles += m.triangles();
  }
  const double aspect = 1280.0 / 720.0;
  auto cam = service::defaultCamera(s.bounds, hlod::UpAxis::Z, 50.0, aspect);
  if (closeUp) cam.position = cam.target + (cam.position - cam.target) * 0.15;
  double zNear = 0.1, zFar = 1e5;
  service::clipPlanes(cam, s.bounds, zNear, zFar);
  const auto view =
      renderer::makeFrameView(cam.position, cam.target, cam.up, cam.fovY, aspect, zNear, zFar);
  s.renderer->drawFrame(view, list);  // warm-up
  double gpuMs = 0.0;
  for (auto _ : state) gpuMs += s.renderer->drawFrame(view, list).gpuMs;
  state.counters["triangles"] = double(triangles);
  state.counters["tris_per_s"] =
      benchmark::Counter(double(triangles), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["gpu_ms"] = gpuMs / double(state.iterations());
  if (glibcHeap) renderer::keepFreedHeap();
}

}  // namespace

// The default city (>= 2 M triangles), whole, at 1280x720.
BENCHMARK_CAPTURE(renderCity, default_city_overview, hlod::kDefaultCityBlocks, false)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
// The same triangles, seen from closer: more pixels per triangle.
BENCHMARK_CAPTURE(renderCity, default_city_close, hlod::kDefaultCityBlocks, true)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

BENCHMARK_CAPTURE(renderCity, default_city_overview_glibc_heap, hlod::kDefaultCityBlocks, false,
                  true)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
BENCHMARK_CAPTURE(renderCity, default_city_close_glibc_heap, hlod::kDefaultCityBlocks, true, true)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

BENCHMARK_MAIN();
