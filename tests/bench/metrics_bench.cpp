// What the image and surface metrics cost: FLIP and SSIM of a 640x360 frame (what `hlodr study`
// computes per studied frame and run), and the surface distance of two 100352-triangle grids
// with 100000 samples a side (what `hlodr study-build` computes per block and level). The values
// they compute are checked by ImageMetricsTest and SurfaceDistanceTest on the same inputs.
// Run: ./metrics_bench  (Google Benchmark flags apply, e.g. --benchmark_filter=Flip)
#include <benchmark/benchmark.h>

#include "../unit/MetricsTestInputs.h"
#include "hlod/metrics/SurfaceDistance.h"

namespace {

using namespace hlod::metrics;

void flipOf640x360(benchmark::State& state) {
  const test::FramePair p = test::frameWithAChangedNinth();
  for (auto _ : state) benchmark::DoNotOptimize(flip(p.reference, p.test));
}
BENCHMARK(flipOf640x360)->Unit(benchmark::kMillisecond);

void ssimOf640x360(benchmark::State& state) {
  const test::FramePair p = test::frameWithAChangedNinth();
  for (auto _ : state) benchmark::DoNotOptimize(ssim(p.reference, p.test));
}
BENCHMARK(ssimOf640x360)->Unit(benchmark::kMillisecond);

void surfaceDistanceOf100kTriangles(benchmark::State& state) {
  const hlod::Mesh rippled = test::rippledSquare(224, 0.02), flat = test::square(224);
  for (auto _ : state) benchmark::DoNotOptimize(surfaceDistance(rippled, flat, 100000));
}
BENCHMARK(surfaceDistanceOf100kTriangles)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
