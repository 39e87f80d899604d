// Selector CPU time per frame on a synthetic city of ~110k nodes (900 blocks, 4 levels below
// hlod_0, level factor 3), for an overview camera (the whole city in view) and a street camera.
// Run: ./selector_bench  (Google Benchmark flags apply, e.g. --benchmark_filter=lakhia)
#include <benchmark/benchmark.h>

#include "../unit/RuntimeTestScene.h"
#include "hlod/runtime/Selector.h"

namespace {

using namespace hlod;

const Skeleton& bigCity() {
  static const Skeleton sk = [] {
    test::SyntheticCity c;
    c.blocksX = 30;
    c.blocksY = 30;
    c.depth = 4;
    return test::makeSyntheticCity(c);
  }();
  return sk;
}

View cameraFor(int kind) {
  View v;
  if (kind == 0) {  // overview: 1.5 km city seen from above one edge
    v.camera.position = {780.0, -700.0, 900.0};
    v.camera.target = {780.0, 780.0, 0.0};
  } else {  // street level, looking along a street
    v.camera.position = {-5.0, 46.0, 1.7};
    v.camera.target = {500.0, 46.0, 1.7};
  }
  v.camera.farPlane = 1e5;
  return v;
}

void selectorFrame(benchmark::State& state, const char* name) {
  const Skeleton& sk = bigCity();
  auto sel = makeSelector(name, sk);
  if (!sel) {
    state.SkipWithError(sel.message().c_str());
    return;
  }
  Selector& s = *sel.value();
  const View v = cameraFor(static_cast<int>(state.range(0)));
  const AllResident resident;
  std::size_t front = 0, visited = 0;
  for (auto _ : state) {
    Selection result = s.select(v, resident);
    s.feedback(2e-5 * result.estimatedCost);  // a steady simulated GPU: 2e-5 ms per triangle
    front = result.front.size();
    visited = result.loadPriorities.size();
    benchmark::DoNotOptimize(result);
  }
  state.counters["nodes"] = static_cast<double>(sk.nodes.size());
  state.counters["front"] = static_cast<double>(front);
  state.counters["visited"] = static_cast<double>(visited);
}

BENCHMARK_CAPTURE(selectorFrame, lakhia, "lakhia")->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(selectorFrame, sse, "sse")->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(selectorFrame, fs, "fs")->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(selectorFrame, full, "full")->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
