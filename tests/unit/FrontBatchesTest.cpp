// A front drawn in batches under a memory cap (hlod/study/FrontBatches.h).
#include <gtest/gtest.h>

#include <algorithm>

#include "hlod/study/FrontBatches.h"

namespace hlod::study {
namespace {

// n nodes of `bytes` decoded bytes each; textured[i] > 0: node i shares the texture of that
// offset, of 1000 bytes.
Skeleton nodesOf(std::size_t n, std::uint64_t bytes, std::vector<std::uint64_t> textured = {}) {
  Skeleton s;
  s.nodes.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    NodeInfo& info = s.nodes[i];
    info.memoryBytes = bytes;
    info.payloadSize = 10;
    if (i < textured.size() && textured[i] > 0) {
      info.textureOffset = textured[i];
      info.textureSize = 5;
      info.textureBytes = 1000;
      info.memoryBytes += 1000;
    }
    s.roots.push_back(std::uint32_t(i));
  }
  return s;
}

std::vector<std::uint32_t> iota(std::uint32_t n) {
  std::vector<std::uint32_t> v(n);
  for (std::uint32_t i = 0; i < n; ++i) v[i] = i;
  return v;
}

TEST(FrontBatches, EachBatchFitsTheCapAndTheBatchesHoldTheFrontOnce) {
  const Skeleton s = nodesOf(10, 300);
  CappedResidency r(s, 1000, true);
  const auto batches = partitionFront(iota(10), r);
  // 300 bytes a node: three fit in 1000, so 3 + 3 + 3 + 1.
  ASSERT_EQ(batches.size(), 4u);
  std::vector<std::uint32_t> all;
  for (const auto& b : batches) {
    EXPECT_LE(r.bytesOf(b), 1000u);
    all.insert(all.end(), b.begin(), b.end());
  }
  EXPECT_EQ(all, iota(10));  // front order kept
}

TEST(FrontBatches, WithoutACapTheFrontIsOneBatch) {
  const Skeleton s = nodesOf(10, 300);
  CappedResidency r(s, 0, true);
  const auto batches = partitionFront(iota(10), r);
  ASSERT_EQ(batches.size(), 1u);
  EXPECT_EQ(batches[0].size(), 10u);
  EXPECT_TRUE(r.ensure(batches[0]).evict.empty());
}

TEST(FrontBatches, ANodeLargerThanTheCapGoesAloneAndIsStillDrawn) {
  const Skeleton s = nodesOf(3, 300);
  Skeleton big = s;
  big.nodes[1].memoryBytes = 5000;
  CappedResidency r(big, 1000, true);
  const auto batches = partitionFront(iota(3), r);
  ASSERT_EQ(batches.size(), 3u);
  EXPECT_EQ(batches[1], std::vector<std::uint32_t>{1});
  for (const auto& b : batches) {
    const auto change = r.ensure(b);
    EXPECT_EQ(change.load, b);
  }
  EXPECT_EQ(r.peakBytes(), 5000u);
}

TEST(FrontBatches, ASharedTextureCountsOnceAndItsNodesStayTogether) {
  // Nodes 0, 2, 4 share texture 77 (1000 bytes): 3 x 100 + 1000 = 1300; nodes 1, 3 have none.
  const Skeleton s = nodesOf(5, 100, {77, 0, 77, 0, 77});
  CappedResidency r(s, 1300, true);
  EXPECT_EQ(r.bytesOf(std::vector<std::uint32_t>{0, 2, 4}), 1300u);
  const auto batches = partitionFront(iota(5), r);
  // The texture's nodes together where the first of them was, then the others.
  ASSERT_EQ(batches.size(), 2u);
  EXPECT_EQ(batches[0], (std::vector<std::uint32_t>{0, 2, 4}));
  EXPECT_EQ(batches[1], (std::vector<std::uint32_t>{1, 3}));
  // Textures off: only the meshes count.
  CappedResidency plain(s, 1300, false);
  EXPECT_EQ(plain.bytesOf(std::vector<std::uint32_t>{0, 2, 4}), 300u);
  EXPECT_EQ(partitionFront(iota(5), plain).size(), 1u);
}

TEST(FrontBatches, EnsureEvictsTheLeastRecentlyUsedOutsideTheBatchUntilItFits) {
  const Skeleton s = nodesOf(6, 300);
  CappedResidency r(s, 900, true);
  r.ensure(std::vector<std::uint32_t>{0, 1});
  r.ensure(std::vector<std::uint32_t>{2});
  EXPECT_EQ(r.bytes(), 900u);
  // 3 and 2: 2 stays (in the batch), 0 then 1 are the oldest; one of them makes room.
  const auto change = r.ensure(std::vector<std::uint32_t>{3, 2});
  EXPECT_EQ(change.load, std::vector<std::uint32_t>{3});
  EXPECT_EQ(change.evict.size(), 1u);
  EXPECT_TRUE(change.evict[0] == 0 || change.evict[0] == 1);
  EXPECT_TRUE(r.isResident(2));
  EXPECT_TRUE(r.isResident(3));
  EXPECT_EQ(r.bytes(), 900u);
  EXPECT_LE(r.peakBytes(), 900u);
}

TEST(FrontBatches, TheNextFrameDrawsWhatIsResidentFirstWithoutLoads) {
  const Skeleton s = nodesOf(8, 300);
  CappedResidency r(s, 900, true);
  for (const auto& b : partitionFront(iota(8), r)) r.ensure(b);
  // Batches {0, 1, 2}, {3, 4, 5}, {6, 7}: the last made room by evicting 3 and 4, so 5, 6, 7
  // stayed; the next frame starts with them, without a load.
  const auto next = partitionFront(iota(8), r);
  ASSERT_FALSE(next.empty());
  EXPECT_EQ(next[0], (std::vector<std::uint32_t>{5, 6, 7}));
  EXPECT_TRUE(r.ensure(next[0]).load.empty());
  std::size_t loads = 0;
  for (std::size_t k = 1; k < next.size(); ++k) loads += r.ensure(next[k]).load.size();
  EXPECT_EQ(loads, 5u);
  EXPECT_LE(r.peakBytes(), 900u);
}

TEST(FrontBatches, EvictingATexturesLastHolderFreesItUnlessTheBatchNeedsIt) {
  // 0 and 1 share texture 5; 2 has none.
  const Skeleton s = nodesOf(3, 100, {5, 5, 0});
  CappedResidency r(s, 1200, true);
  r.ensure(std::vector<std::uint32_t>{0});
  EXPECT_EQ(r.bytes(), 1100u);
  // 1 needs the texture 0 holds: evicting 0 keeps it, so 1 + texture = 1100 fits.
  auto change = r.ensure(std::vector<std::uint32_t>{1});
  EXPECT_TRUE(change.evict.empty());
  EXPECT_EQ(r.bytes(), 1200u);
  // 2 (100 bytes) makes room by evicting 0, the older: the texture stays, held by 1.
  change = r.ensure(std::vector<std::uint32_t>{2});
  EXPECT_EQ(change.evict, std::vector<std::uint32_t>{0});
  EXPECT_EQ(r.bytes(), 1200u);
  // 0 again: 1 goes, its texture's last holder, but 0 needs it, so it stays counted once.
  change = r.ensure(std::vector<std::uint32_t>{0, 2});
  EXPECT_EQ(change.evict, std::vector<std::uint32_t>{1});
  EXPECT_EQ(change.load, std::vector<std::uint32_t>{0});
  EXPECT_EQ(r.bytes(), 1200u);
  // 2 alone with room to spare: 0 stays, nothing moves.
  change = r.ensure(std::vector<std::uint32_t>{2});
  EXPECT_TRUE(change.evict.empty() && change.load.empty());
  // A node without texture that does not fit evicts 0 and the texture goes with it.
  Skeleton more = nodesOf(4, 100, {5, 5, 0, 0});
  more.nodes[3].memoryBytes = 1100;
  CappedResidency q(more, 1200, true);
  q.ensure(std::vector<std::uint32_t>{0});
  change = q.ensure(std::vector<std::uint32_t>{3});
  EXPECT_EQ(change.evict, std::vector<std::uint32_t>{0});
  EXPECT_EQ(q.bytes(), 1100u);
}

}  // namespace
}  // namespace hlod::study
