// The decoded node cache shared by the sessions of one store.
#include <gtest/gtest.h>

#include "RuntimeTestScene.h"
#include "hlod/runtime/Loader.h"
#include "hlod/runtime/NodeCache.h"

using namespace hlod;

namespace {

LocalMesh meshOf(int triangles) {
  LocalMesh m;
  m.indices.assign(std::size_t(triangles) * 3, 0u);
  return m;
}

}  // namespace

TEST(NodeCache, ANodeDecodedOnceIsSharedWhileAnyoneHoldsIt) {
  NodeCache cache;  // no cap: sharing only
  ASSERT_TRUE(cache.reserve(100));
  auto a = cache.insert(7, meshOf(5), 100);
  auto b = cache.find(7);
  EXPECT_EQ(a.get(), b.get());
  EXPECT_EQ(cache.liveBytes(), 100u);
  a.reset();
  EXPECT_EQ(cache.liveBytes(), 100u);  // b still holds it
  b.reset();
  EXPECT_EQ(cache.liveBytes(), 0u);
  EXPECT_EQ(cache.find(7), nullptr);  // without a cap nothing is kept for later
}

TEST(NodeCache, ASecondInsertOfTheSameNodeReturnsTheFirstCopy) {
  NodeCache cache;
  ASSERT_TRUE(cache.reserve(100));
  ASSERT_TRUE(cache.reserve(100));
  auto a = cache.insert(3, meshOf(1), 100);
  auto b = cache.insert(3, meshOf(1), 100);  // decoded by another session meanwhile
  EXPECT_EQ(a.get(), b.get());
  EXPECT_EQ(cache.liveBytes(), 100u);  // counted once, the second reservation given back
}

TEST(NodeCache, TheCapKeepsUnheldPayloadsUntilRoomIsNeededAndNeverDropsHeldOnes) {
  NodeCache cache(250);
  ASSERT_TRUE(cache.reserve(100));
  auto held = cache.insert(1, meshOf(1), 100);
  ASSERT_TRUE(cache.reserve(100));
  cache.insert(2, meshOf(1), 100);  // nobody holds it: kept for a later session
  EXPECT_EQ(cache.liveBytes(), 200u);
  EXPECT_NE(cache.find(2), nullptr);
  // 100 more fit only once node 2 goes; node 1 is held and stays.
  ASSERT_TRUE(cache.reserve(100));
  EXPECT_EQ(cache.find(2), nullptr);
  EXPECT_EQ(cache.find(1).get(), held.get());
  EXPECT_EQ(cache.liveBytes(), 200u);  // node 1 + the reservation
  // Nothing unheld is left to drop: a further 100 do not fit.
  EXPECT_FALSE(cache.reserve(100));
  cache.release(100);
  EXPECT_EQ(cache.liveBytes(), 100u);
}

TEST(NodeCache, TwoLoadersOfOneStoreReadEachNodeOnce) {
  test::SyntheticCity city;
  city.depth = 1;
  test::MemoryNodeSource source(test::makeSyntheticCity(city));
  LoaderParams p;
  p.cache = std::make_shared<NodeCache>();
  Loader a(source, p), b(source, p);
  ASSERT_TRUE(a.loadRoots().ok());
  ASSERT_TRUE(b.loadRoots().ok());
  const Skeleton& sk = source.skeleton();
  for (std::uint32_t r : sk.roots) {
    EXPECT_EQ(source.reads(r), 1) << "root " << r;
    EXPECT_TRUE(b.isResident(r));
    EXPECT_EQ(a.residentPayload(r).get(), b.residentPayload(r).get());
  }
  EXPECT_EQ(b.counters().cacheHits, sk.roots.size());
  EXPECT_EQ(a.counters().cacheHits, 0u);
  // Below hlod_0 too: what a loaded, b takes without a read.
  const std::uint32_t child = sk.nodes[sk.roots[0]].firstChild;
  const LoadRequest want[] = {{child, 1.0}};
  a.setWanted(want);
  while (a.step()) {
  }
  b.setWanted(want);
  while (b.step()) {
  }
  EXPECT_TRUE(b.isResident(child));
  EXPECT_EQ(source.reads(child), int((sk.nodes[child].payloadSize + 65535) / 65536));
  EXPECT_EQ(b.counters().bytesRead, 0u);  // everything came from a's decodes
  EXPECT_GT(a.counters().bytesRead, 0u);
}

TEST(NodeCache, AServerCapHeldByOtherSessionsMakesALoaderWaitNotFail) {
  test::SyntheticCity city;
  city.depth = 1;
  test::MemoryNodeSource source(test::makeSyntheticCity(city));
  const Skeleton& sk = source.skeleton();
  std::uint64_t roots = 0;
  for (std::uint32_t r : sk.roots) roots += sk.nodes[r].memoryBytes;
  LoaderParams p;
  p.cache = std::make_shared<NodeCache>(roots);  // room for hlod_0 only
  Loader a(source, p);
  ASSERT_TRUE(a.loadRoots().ok());
  const std::uint32_t child = sk.nodes[sk.roots[0]].firstChild;
  const LoadRequest want[] = {{child, 1.0}};
  a.setWanted(want);
  EXPECT_FALSE(a.step());  // no room: idle, not an error
  EXPECT_FALSE(a.isResident(child));
  EXPECT_EQ(a.counters().loadErrors, 0u);
  EXPECT_LE(p.cache->liveBytes(), roots);
}
