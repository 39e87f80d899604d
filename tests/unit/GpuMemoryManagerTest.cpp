// The GPU memory manager (Manocha sec. 5.1.3) without GL: which node it frees for room.
#include <gtest/gtest.h>

#include "RuntimeTestScene.h"
#include "hlod/runtime/GpuMemoryManager.h"

using namespace hlod;

namespace {

// One block: root 0 with children 1..3, each with children (4..6, 7..9, 10..12).
Skeleton tree() {
  test::SyntheticCity c;
  c.blocksX = c.blocksY = 1;
  c.depth = 2;
  return test::makeSyntheticCity(c);
}

}  // namespace

TEST(GpuMemoryManager, FreesTheLeastRecentlyDrawnLeafFirstAndNeverARootOrAParent) {
  const Skeleton sk = tree();
  ASSERT_EQ(sk.nodes[0].firstChild, 1u);
  GpuMemoryManager m(sk, 1000);
  for (std::uint32_t n : {0u, 1u, 2u, 4u, 7u}) m.uploaded(n);
  const std::vector<std::uint32_t> f1 = {4, 2};
  m.drawn(f1);
  const std::vector<std::uint32_t> f2 = {7};
  m.drawn(f2);
  // 1 and 2 have children on the GPU, 0 is a root, 7 was drawn last frame: 4 goes (for 10,
  // whose siblings are 11 and 12).
  EXPECT_EQ(m.nextVictim(10), 4u);
  m.freed(4);
  // Now 1 has no child on the GPU and was never drawn: the least recently drawn.
  EXPECT_EQ(m.nextVictim(10), 1u);
  m.freed(1);
  EXPECT_EQ(m.nextVictim(10), kNoNode);  // 2 has 7 below it, 7 was drawn last frame
}

TEST(GpuMemoryManager, NeverFreesASiblingOfTheNodeThatNeedsRoom) {
  const Skeleton sk = tree();
  GpuMemoryManager m(sk, 1000);
  for (std::uint32_t n : {0u, 1u, 4u, 5u}) m.uploaded(n);
  m.drawn(std::vector<std::uint32_t>{1});
  m.drawn(std::vector<std::uint32_t>{0});
  // 4 and 5 are 6's siblings: freeing one for 6 would bring it back next frame for the group.
  EXPECT_EQ(m.nextVictim(6), kNoNode);
  EXPECT_NE(m.nextVictim(10), kNoNode);
}

TEST(GpuMemoryManager, NoBudgetFreesNothingAndFitsEverything) {
  const Skeleton sk = tree();
  GpuMemoryManager none(sk, 0), some(sk, 100);
  none.uploaded(4);
  EXPECT_EQ(none.nextVictim(10), kNoNode);
  EXPECT_TRUE(none.fits(1ull << 40, 1ull << 40));
  EXPECT_TRUE(some.fits(60, 40));
  EXPECT_FALSE(some.fits(61, 40));
  EXPECT_FALSE(some.fits(0, 101));
}
