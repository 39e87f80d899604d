// The GPU memory budget (Manocha sec. 5.1.3, hlod/runtime/GpuMemoryManager.h) on a real
// (software) GL context: a budget below what the front needs draws coarser, settles, and never
// stalls or trades the same nodes back and forth.
#include <gtest/gtest.h>

#include "BoxScene.h"

using gltest::GlRig;

namespace {

// Above the wall, looking down at the block: the full selector wants its four boxes.
hlod::CameraSample above(const GlRig& rig, double t) {
  return rig.at(t, {25, 0, 40}, {25, 0.1, 0});
}

}  // namespace

TEST(GpuBudget, ABudgetBelowTheFrontDrawsCoarserAndSettlesWithoutChurn) {
  // The roots (wall, block, side box) fit, and two of the block's four boxes.
  GlRig probe(hlod::OcclusionMode::Off);
  REQUIRE_RIG(probe);
  probe.frame(above(probe, 0));
  ASSERT_TRUE(probe.drawn(2) && probe.drawn(5));  // unbudgeted: the four boxes
  const std::uint64_t rootsOnly = [&] {
    GlRig r(hlod::OcclusionMode::Off);
    return r.gpu->gpuBytes();  // after start(): hlod_0 only
  }();
  const std::uint64_t box = (probe.gpu->gpuBytes() - rootsOnly) / 4;
  ASSERT_GT(box, 0u);

  GlRig rig(hlod::OcclusionMode::Off, false, rootsOnly + 2 * box + box / 2);
  REQUIRE_RIG(rig);
  std::uint32_t evictions = 0, uploads = 0;
  for (int f = 0; f < 10; ++f) {
    const hlod::FrameRecord r = rig.frame(above(rig, f / 30.0));
    EXPECT_LE(r.gpuBytes, rootsOnly + 2 * box + box / 2) << "frame " << f;
    // The first frame waits for the loader (settled); after that nothing waits.
    if (f > 0) {
      EXPECT_EQ(r.stalls, 0u) << "frame " << f;
    }
    // Coarser: the block as one node, its boxes not all on the GPU.
    EXPECT_TRUE(rig.drawn(1)) << "frame " << f;
    if (f >= 2) evictions += r.gpuEvictions, uploads += r.uploads;
  }
  // Settled: nothing traded back and forth after the first frames.
  EXPECT_EQ(evictions, 0u);
  EXPECT_EQ(uploads, 0u);
}
