// The loader's emulated link on an injected clock (LoaderParams::clock): throttling and latency
// take exactly the emulated time on a ManualLinkClock, without sleeping.
#include <gtest/gtest.h>

#include <memory>

#include "ManualLinkClock.h"
#include "RuntimeTestScene.h"
#include "hlod/runtime/Loader.h"

namespace hlod {
namespace {

using test::makeSyntheticCity;
using test::ManualLinkClock;
using test::MemoryNodeSource;
using test::SyntheticCity;

// 2 x 2 blocks, two levels below hlod_0, 48000-byte payloads (1000 triangles of 48 bytes).
constexpr SyntheticCity kCity{.blocksX = 2, .blocksY = 2, .depth = 2};

TEST(LinkClock, AThrottledStepWaitsTheLatencyOfANewRequestAndTheTransferOnTheGivenClock) {
  MemoryNodeSource src(makeSyntheticCity(kCity));
  const Skeleton& sk = src.skeleton();
  auto clock = std::make_shared<ManualLinkClock>();
  LoaderParams p;
  p.chunkBytes = 24000;  // two chunks a node
  p.ioLatencyMs = 5.0;
  p.ioMbps = 96.0;  // 24000 bytes = 192000 bits: 2 ms
  p.clock = clock;
  Loader loader(src, p);
  ASSERT_TRUE(loader.loadRoots().ok());
  // A child of the second root (its payload does not follow the last one read) and its sibling
  // stored right after it.
  const std::uint32_t a = sk.nodes[sk.roots[1]].firstChild, b = a + 1;
  ASSERT_EQ(sk.nodes[b].payloadOffset, sk.nodes[a].payloadOffset + sk.nodes[a].payloadSize);
  const std::vector<LoadRequest> wanted = {{a, 1.0}, {b, 0.5}};
  loader.setWanted(wanted);
  auto timedStep = [&] {
    const double t0 = clock->elapsedMs();
    EXPECT_TRUE(loader.step());
    return clock->elapsedMs() - t0;
  };
  const std::uint64_t requests = loader.counters().requests;
  EXPECT_NEAR(timedStep(), 5.0 + 2.0, 1e-6);  // a's first chunk, a new request: latency, transfer
  EXPECT_NEAR(timedStep(), 2.0, 1e-6);        // its second chunk (and the decode): same request
  ASSERT_TRUE(loader.isResident(a));
  EXPECT_NEAR(timedStep(), 2.0, 1e-6);  // b, stored right after a, continues the read
  EXPECT_EQ(loader.counters().requests, requests + 1);
}

TEST(LinkClock, ARequestMadeAheadWaitsOnlyWhatItsLeadTimeLeftOfTheLatency) {
  MemoryNodeSource src(makeSyntheticCity(kCity));
  const Skeleton& sk = src.skeleton();
  // The last children of the first two roots: neither stored right after the other or a root.
  const std::uint32_t first =
      sk.nodes[sk.roots[0]].firstChild + sk.nodes[sk.roots[0]].childCount - 1;
  const std::uint32_t second =
      sk.nodes[sk.roots[1]].firstChild + sk.nodes[sk.roots[1]].childCount - 1;
  auto end = [&](std::uint32_t n) { return sk.nodes[n].payloadOffset + sk.nodes[n].payloadSize; };
  ASSERT_NE(sk.nodes[second].payloadOffset, end(first));
  for (std::uint32_t r : sk.roots) {
    ASSERT_NE(sk.nodes[first].payloadOffset, end(r));
    ASSERT_NE(sk.nodes[second].payloadOffset, end(r));
  }
  auto clock = std::make_shared<ManualLinkClock>();
  LoaderParams p;
  p.chunkBytes = 48000;  // one chunk a node
  p.ioMbps = 96.0;       // 48000 bytes in 4 ms
  p.ioLatencyMs = 10.0;  // the first waits it whole; the second's runs during the first
  p.ioRequests = 2;
  p.clock = clock;
  Loader loader(src, p);
  ASSERT_TRUE(loader.loadRoots().ok());
  const double before = loader.counters().latencyMs;
  const std::vector<LoadRequest> wanted = {{first, 2.0}, {second, 1.0}};
  loader.setWanted(wanted);
  while (loader.step()) {
  }
  ASSERT_TRUE(loader.isResident(first) && loader.isResident(second));
  // The first waits its 10 ms and streams for 4 ms; the second, requested ahead when the first
  // was chosen, has had those 14 ms of its 10 ms latency: it waits no more.
  EXPECT_NEAR(loader.counters().latencyMs - before, 10.0, 1e-6);
}

}  // namespace
}  // namespace hlod
