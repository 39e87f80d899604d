#include <chrono>
#include <random>

#include <gtest/gtest.h>

#include "ManualLinkClock.h"
#include "RuntimeTestScene.h"
#include "hlod/runtime/LakhiaSelector.h"
#include "hlod/runtime/Loader.h"

namespace hlod {
namespace {

using test::GatedLinkClock;
using test::makeSyntheticCity;
using test::ManualLinkClock;
using test::MemoryNodeSource;
using test::SyntheticCity;

constexpr std::uint64_t kNodeMemory = 96000;

SyntheticCity smallCity() {
  SyntheticCity c;
  c.blocksX = 2;
  c.blocksY = 2;
  c.depth = 2;
  c.triPerNode = 1000;
  c.bytesPerTri = 48;  // 48000-byte payloads, 96000 bytes decoded (kNodeMemory)
  return c;
}

std::vector<LoadRequest> requests(std::initializer_list<std::pair<std::uint32_t, double>> l) {
  std::vector<LoadRequest> out;
  for (auto [n, p] : l) out.push_back({n, p});
  return out;
}

std::uint64_t rootBytes(const Skeleton& sk) {
  std::uint64_t b = 0;
  for (std::uint32_t r : sk.roots) b += sk.nodes[r].memoryBytes;
  return b;
}

TEST(Loader, LoadRootsMakesEveryHlod0NodeResidentWithLoadedEvents) {
  MemoryNodeSource src(makeSyntheticCity(smallCity()));
  Loader loader(src);
  ASSERT_TRUE(loader.loadRoots().ok());
  for (std::uint32_t r : src.skeleton().roots) {
    EXPECT_TRUE(loader.isResident(r));
    ASSERT_NE(loader.residentPayload(r), nullptr);
    EXPECT_EQ(loader.residentPayload(r)->triangleCount(), 1000u);
  }
  EXPECT_FALSE(loader.isResident(src.skeleton().nodes[0].firstChild));
  EXPECT_EQ(loader.residentPayload(src.skeleton().nodes[0].firstChild), nullptr);
  const auto events = loader.drainEvents();
  ASSERT_EQ(events.size(), src.skeleton().roots.size());
  for (const LoaderEvent& e : events) {
    EXPECT_EQ(e.kind, LoaderEvent::Kind::Loaded);
    EXPECT_NE(e.mesh, nullptr);
  }
  EXPECT_TRUE(loader.drainEvents().empty());
  EXPECT_EQ(loader.counters().residentBytes, rootBytes(src.skeleton()));
  EXPECT_FALSE(loader.isResident(1u << 30));  // out of range: not resident, no crash
}

TEST(Loader, StepReadsOneChunkAtATimeAndLoadsTheHighestPriorityFirst) {
  MemoryNodeSource src(makeSyntheticCity(smallCity()));
  LoaderParams p;
  p.chunkBytes = 16000;  // 3 chunks per node
  Loader loader(src, p);
  ASSERT_TRUE(loader.loadRoots().ok());
  loader.drainEvents();
  const std::uint32_t a = src.skeleton().nodes[0].firstChild;
  const std::uint32_t b = a + 1;
  const auto req = requests({{a, 1.0}, {b, 5.0}});
  loader.setWanted(req);
  EXPECT_TRUE(loader.step());
  EXPECT_EQ(loader.currentLoad(), b);
  EXPECT_FALSE(loader.isResident(b));
  EXPECT_TRUE(loader.step());
  EXPECT_TRUE(loader.step());
  EXPECT_TRUE(loader.isResident(b));
  EXPECT_EQ(src.reads(b), 3);
  EXPECT_TRUE(loader.step());
  EXPECT_TRUE(loader.step());
  EXPECT_TRUE(loader.step());
  EXPECT_TRUE(loader.isResident(a));
  EXPECT_FALSE(loader.step());  // nothing left
  const auto events = loader.drainEvents();
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].node, b);
  EXPECT_EQ(events[1].node, a);
  const LoaderCounters c = loader.counters();
  EXPECT_EQ(c.loadsFinished, src.skeleton().roots.size() + 2);
  EXPECT_EQ(c.inFlightBytes, 0u);
}

TEST(Loader, SwitchesToANewNodeWhenPrioritiesChangeMidLoadAndResumesTheOldOne) {
  MemoryNodeSource src(makeSyntheticCity(smallCity()));
  LoaderParams p;
  p.chunkBytes = 16000;
  Loader loader(src, p);
  ASSERT_TRUE(loader.loadRoots().ok());
  const std::uint32_t a = src.skeleton().nodes[0].firstChild;
  const std::uint32_t b = src.skeleton().nodes[1].firstChild;
  loader.setWanted(requests({{a, 5.0}, {b, 1.0}}));
  ASSERT_TRUE(loader.step());
  EXPECT_EQ(loader.currentLoad(), a);
  // The camera turned: b matters more now.
  loader.setWanted(requests({{a, 1.0}, {b, 5.0}}));
  ASSERT_TRUE(loader.step());
  EXPECT_EQ(loader.currentLoad(), b);
  EXPECT_EQ(loader.counters().preemptions, 1u);
  while (loader.step()) {
  }
  EXPECT_TRUE(loader.isResident(a));
  EXPECT_TRUE(loader.isResident(b));
  EXPECT_EQ(src.reads(a), 3);  // the kept partial buffer was resumed, not re-read
  const auto log = src.readLog();
  const std::vector<std::uint32_t> tail(log.end() - 6, log.end());
  EXPECT_EQ(tail, (std::vector<std::uint32_t>{a, b, b, b, a, a}));
}

TEST(Loader, DroppingPartialBuffersRereadsThePreemptedNode) {
  MemoryNodeSource src(makeSyntheticCity(smallCity()));
  LoaderParams p;
  p.chunkBytes = 16000;
  p.keepPartial = false;
  Loader loader(src, p);
  ASSERT_TRUE(loader.loadRoots().ok());
  const std::uint32_t a = src.skeleton().nodes[0].firstChild;
  const std::uint32_t b = src.skeleton().nodes[1].firstChild;
  loader.setWanted(requests({{a, 5.0}, {b, 1.0}}));
  ASSERT_TRUE(loader.step());
  loader.setWanted(requests({{a, 1.0}, {b, 5.0}}));
  while (loader.step()) {
  }
  EXPECT_TRUE(loader.isResident(a));
  EXPECT_EQ(src.reads(a), 4);
  EXPECT_EQ(loader.counters().inFlightBytes, 0u);
}

TEST(Loader, LoadsANodeOnlyAfterItsParent) {
  MemoryNodeSource src(makeSyntheticCity(smallCity()));
  Loader loader(src);
  ASSERT_TRUE(loader.loadRoots().ok());
  const std::uint32_t child = src.skeleton().nodes[0].firstChild;
  const std::uint32_t grandchild = src.skeleton().nodes[child].firstChild;
  loader.setWanted(requests({{grandchild, 10.0}}));
  EXPECT_FALSE(loader.step());
  loader.setWanted(requests({{grandchild, 10.0}, {child, 1.0}}));
  while (loader.step()) {
  }
  EXPECT_TRUE(loader.isResident(child));
  EXPECT_TRUE(loader.isResident(grandchild));
}

TEST(Loader, MemoryCapIsNeverExceededAndHlod0IsNeverUnloaded) {
  SyntheticCity c = smallCity();
  c.blocksX = 4;
  c.depth = 3;
  MemoryNodeSource src(makeSyntheticCity(c));
  const Skeleton& sk = src.skeleton();
  LoaderParams p;
  p.chunkBytes = 20000;
  p.capBytes = rootBytes(sk) + 6 * kNodeMemory + 1000;  // room for 6 more nodes
  Loader loader(src, p);
  ASSERT_TRUE(loader.loadRoots().ok());
  EXPECT_FALSE(loader.counters().rootsExceedCap);
  loader.drainEvents();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pri(0.0, 1.0);
  std::uint64_t finished = 0;
  for (int frame = 0; frame < 300; ++frame) {
    std::vector<LoadRequest> req;
    for (std::uint32_t n = 0; n < sk.nodes.size(); ++n) req.push_back({n, pri(rng)});
    loader.setWanted(req);
    for (int s = 0; s < 4; ++s) {
      loader.step();
      const LoaderCounters k = loader.counters();
      ASSERT_LE(k.residentBytes + k.inFlightBytes, p.capBytes);
      ASSERT_LE(k.peakBytes, p.capBytes);
    }
    for (std::uint32_t r : sk.roots) ASSERT_TRUE(loader.isResident(r));
    for (const LoaderEvent& e : loader.drainEvents()) {
      ASSERT_NE(sk.nodes[e.node].parent, kNoNode) << "hlod_0 node " << e.node << " touched";
      // Resident set stays closed upwards: a loaded node's parent is resident.
      if (e.kind == LoaderEvent::Kind::Loaded) {
        EXPECT_TRUE(loader.isResident(sk.nodes[e.node].parent) || !loader.isResident(e.node));
      }
    }
    finished = loader.counters().loadsFinished;
  }
  EXPECT_GT(loader.counters().unloads, 10u);
  EXPECT_GT(finished, sk.roots.size() + 20);
}

TEST(Loader, PaperMemoryBoundOnCostIsKept) {
  MemoryNodeSource src(makeSyntheticCity(smallCity()));
  const Skeleton& sk = src.skeleton();
  LoaderParams p;
  p.c_memory = 1.0;
  p.maxMemory = sk.roots.size() * 1000.0 + 3 * 1000.0 + 1.0;  // cost: roots + 3 nodes
  Loader loader(src, p);
  ASSERT_TRUE(loader.loadRoots().ok());
  std::vector<LoadRequest> req;
  for (std::uint32_t n = 0; n < sk.nodes.size(); ++n) req.push_back({n, 1.0 + n});
  loader.setWanted(req);
  while (loader.step()) {
    ASSERT_LT(p.c_memory * loader.counters().residentCost, p.maxMemory);
  }
  EXPECT_EQ(loader.counters().residentNodes, sk.roots.size() + 3);
}

TEST(Loader, UnloadsTheLowestPriorityNodeFirst) {
  MemoryNodeSource src(makeSyntheticCity(smallCity()));
  const Skeleton& sk = src.skeleton();
  LoaderParams p;
  p.capBytes = rootBytes(sk) + 2 * kNodeMemory;
  Loader loader(src, p);
  ASSERT_TRUE(loader.loadRoots().ok());
  const std::uint32_t a = sk.nodes[0].firstChild, b = a + 1, c = a + 2;
  loader.setWanted(requests({{a, 3.0}, {b, 2.0}}));
  while (loader.step()) {
  }
  loader.drainEvents();
  loader.setWanted(requests({{a, 3.0}, {b, 2.0}, {c, 2.5}}));
  while (loader.step()) {
  }
  EXPECT_TRUE(loader.isResident(a));
  EXPECT_FALSE(loader.isResident(b));
  EXPECT_TRUE(loader.isResident(c));
  const auto events = loader.drainEvents();
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, LoaderEvent::Kind::Unloaded);
  EXPECT_EQ(events[0].node, b);
  EXPECT_EQ(events[1].node, c);
  // A less important node does not push out more important ones.
  loader.setWanted(requests({{a, 3.0}, {b, 0.5}, {c, 2.5}}));
  EXPECT_FALSE(loader.step());
}

class FailingSource final : public NodeSource {
 public:
  explicit FailingSource(const NodeSource& inner, std::uint32_t bad) : inner_(inner), bad_(bad) {}
  const Skeleton& skeleton() const override { return inner_.skeleton(); }
  Status readPayloadChunk(std::uint32_t node, std::uint64_t offset,
                          std::span<std::byte> out) const override {
    if (node == bad_) return makeError("disk on fire");
    return inner_.readPayloadChunk(node, offset, out);
  }
  Result<LocalMesh> decodePayload(std::uint32_t node,
                                  std::span<const std::byte> bytes) const override {
    return inner_.decodePayload(node, bytes);
  }

 private:
  const NodeSource& inner_;
  std::uint32_t bad_;
};

TEST(Loader, AReadErrorIsCountedAndNotRetried) {
  MemoryNodeSource inner(makeSyntheticCity(smallCity()));
  const std::uint32_t bad = inner.skeleton().nodes[0].firstChild;
  FailingSource src(inner, bad);
  Loader loader(src);
  ASSERT_TRUE(loader.loadRoots().ok());
  loader.setWanted(requests({{bad, 5.0}, {bad + 1, 1.0}}));
  while (loader.step()) {
  }
  EXPECT_FALSE(loader.isResident(bad));
  EXPECT_TRUE(loader.isResident(bad + 1));
  EXPECT_EQ(loader.counters().loadErrors, 1u);
  EXPECT_NE(loader.lastError().find("disk on fire"), std::string::npos);
}

TEST(Loader, LoadRootsReportsABrokenHlod0Node) {
  MemoryNodeSource inner(makeSyntheticCity(smallCity()));
  FailingSource src(inner, inner.skeleton().roots[1]);
  Loader loader(src);
  const Status s = loader.loadRoots();
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("hlod_0 node"), std::string::npos);
}

TEST(Loader, PrefetchLoadsNodesThatNoFrameWantsYet) {
  MemoryNodeSource src(makeSyntheticCity(smallCity()));
  Loader loader(src);
  ASSERT_TRUE(loader.loadRoots().ok());
  const std::uint32_t a = src.skeleton().nodes[2].firstChild;
  loader.setWanted({});
  loader.prefetch(requests({{a, 1.0}}));
  EXPECT_TRUE(loader.waitUntilResident(std::vector<std::uint32_t>{a}, std::chrono::seconds(1)));
}

TEST(Loader, ThrottlingEmulatesLatencyPerRequestAndBandwidth) {
  MemoryNodeSource src(makeSyntheticCity(smallCity()));
  const Skeleton& sk = src.skeleton();
  auto clock = std::make_shared<ManualLinkClock>();
  LoaderParams p;
  p.chunkBytes = 24000;  // two chunks a node
  p.ioLatencyMs = 5.0;
  p.ioMbps = 96.0;  // 24000 bytes = 192000 bits: 2 ms
  p.clock = clock;
  Loader loader(src, p);
  ASSERT_TRUE(loader.loadRoots().ok());
  const std::uint64_t rootRequests = loader.counters().requests;
  EXPECT_GE(rootRequests, 1u);
  // A child of the second root: its payload does not follow the last one read.
  const std::uint32_t a = sk.nodes[sk.roots[1]].firstChild, b = a + 1;
  ASSERT_EQ(sk.nodes[b].parent, sk.nodes[a].parent);
  ASSERT_EQ(sk.nodes[b].payloadOffset, sk.nodes[a].payloadOffset + sk.nodes[a].payloadSize);
  loader.setWanted(requests({{a, 1.0}, {b, 0.5}}));
  // The emulated time one step took on the link.
  auto timedStep = [&] {
    const double t0 = clock->elapsedMs();
    EXPECT_TRUE(loader.step());
    return clock->elapsedMs() - t0;
  };
  EXPECT_NEAR(timedStep(), 5.0 + 2.0, 1e-6);  // a new request: latency and transfer
  EXPECT_EQ(loader.counters().requests, rootRequests + 1);
  EXPECT_FALSE(loader.isResident(a));
  EXPECT_NEAR(timedStep(), 2.0, 1e-6);  // its second chunk goes on with the same request
  ASSERT_TRUE(loader.isResident(a));    // and the decode finishes it in that step
  EXPECT_NEAR(timedStep(), 2.0, 1e-6);  // b is stored right after a: still the same request
  EXPECT_EQ(loader.counters().requests, rootRequests + 1);
  EXPECT_NEAR(timedStep(), 2.0, 1e-6);
  EXPECT_TRUE(loader.isResident(b));
  const double loaded = clock->elapsedMs();
  EXPECT_FALSE(loader.step());  // nothing more is wanted: no time passes
  EXPECT_EQ(clock->elapsedMs(), loaded);
}

TEST(Loader, RequestsInFlightHideTheLatencyBehindTransfers) {
  MemoryNodeSource src(makeSyntheticCity(smallCity()));
  const Skeleton& sk = src.skeleton();
  // Last children of the four roots: none stored right after another or after the roots, so
  // each is a new request.
  std::vector<std::uint32_t> nodes;
  for (std::uint32_t r : sk.roots)
    nodes.push_back(sk.nodes[r].firstChild + sk.nodes[r].childCount - 1);
  ASSERT_EQ(nodes.size(), 4u);
  auto end = [&](std::uint32_t n) { return sk.nodes[n].payloadOffset + sk.nodes[n].payloadSize; };
  for (std::uint32_t n : nodes) {
    for (std::uint32_t m : nodes) ASSERT_NE(sk.nodes[n].payloadOffset, end(m));
    for (std::uint32_t r : sk.roots) ASSERT_NE(sk.nodes[n].payloadOffset, end(r));
  }
  LoaderParams p;
  p.chunkBytes = 48000;  // one chunk a node
  // Emulated latency waited for while loading `nodes`, with `inFlight` requests on the link.
  auto latencyFor = [&](std::size_t inFlight) {
    p.ioRequests = inFlight;
    p.clock = std::make_shared<ManualLinkClock>();
    Loader loader(src, p);
    EXPECT_TRUE(loader.loadRoots().ok());
    const LoaderCounters before = loader.counters();
    loader.setWanted(
        requests({{nodes[0], 4.0}, {nodes[1], 3.0}, {nodes[2], 2.0}, {nodes[3], 1.0}}));
    while (loader.step()) {
    }
    for (std::uint32_t n : nodes) EXPECT_TRUE(loader.isResident(n));
    EXPECT_EQ(loader.counters().requests - before.requests, 4u);  // as many either way
    return loader.counters().latencyMs - before.latencyMs;
  };
  p.ioMbps = 38.4;  // 48000 bytes in 10 ms: longer than the latency
  p.ioLatencyMs = 8.0;
  EXPECT_NEAR(latencyFor(1), 4 * 8.0, 1e-9);  // one at a time: every request waits
  // Four in flight: the three behind the first were requested with it and waited during its
  // latency and transfer (18 ms): only the first one waits.
  EXPECT_NEAR(latencyFor(4), 8.0, 1e-9);
  // A transfer shorter than the latency hides only part of it. Two in flight, 10 ms latency, 4 ms
  // transfers: nodes[1], requested with nodes[0] at 0 ms, has had 14 ms when its turn comes (no
  // wait); nodes[2], requested when nodes[1] is chosen (14 ms), has had 4 ms of its 10 (waits 6);
  // nodes[3], requested when nodes[2] is chosen (18 ms), has had those 6 and a 4 ms transfer.
  p.ioMbps = 96.0;
  p.ioLatencyMs = 10.0;
  EXPECT_NEAR(latencyFor(2), 10.0 + 0.0 + 6.0 + 0.0, 1e-9);

  // A request that drops out of the window is cancelled: back in it, it waits all over again.
  p.ioMbps = 38.4;
  p.ioLatencyMs = 8.0;
  p.ioRequests = 2;
  p.clock = std::make_shared<ManualLinkClock>();
  Loader loader(src, p);
  ASSERT_TRUE(loader.loadRoots().ok());
  const double before = loader.counters().latencyMs;
  loader.setWanted(requests({{nodes[0], 2.0}, {nodes[1], 1.0}}));  // nodes[1] requested ahead
  ASSERT_TRUE(loader.step());                                      // nodes[0] read
  loader.setWanted(requests({{nodes[0], 2.0}}));                   // nodes[1] cancelled
  while (loader.step()) {
  }
  loader.setWanted(requests({{nodes[1], 1.0}}));
  while (loader.step()) {
  }
  EXPECT_TRUE(loader.isResident(nodes[1]));
  EXPECT_NEAR(loader.counters().latencyMs - before, 2 * 8.0, 1e-9);
}

TEST(Loader, TakesTheNextSiblingUnlessSomethingFarMoreImportantWaits) {
  MemoryNodeSource src(makeSyntheticCity(smallCity()));
  const Skeleton& sk = src.skeleton();
  Loader loader(src, LoaderParams{});
  ASSERT_TRUE(loader.loadRoots().ok());
  const std::uint32_t a = sk.nodes[sk.roots[0]].firstChild, b = a + 1;
  const std::uint32_t other = sk.nodes[sk.roots[1]].firstChild;
  // other is a bit more important than a's sibling b: b still comes first, continuing the read.
  loader.setWanted(requests({{a, 3.0}, {other, 2.0}, {b, 1.0}}));
  while (!loader.isResident(a)) ASSERT_TRUE(loader.step());
  while (!loader.isResident(b) && !loader.isResident(other)) ASSERT_TRUE(loader.step());
  EXPECT_TRUE(loader.isResident(b));
  EXPECT_FALSE(loader.isResident(other));
  // Far more important (more than 1 / c_siblingRatio times): it goes first.
  Loader second(src, LoaderParams{});
  ASSERT_TRUE(second.loadRoots().ok());
  second.setWanted(requests({{a, 30.0}, {other, 20.0}, {b, 1.0}}));
  while (!second.isResident(a)) ASSERT_TRUE(second.step());
  while (!second.isResident(b) && !second.isResident(other)) ASSERT_TRUE(second.step());
  EXPECT_TRUE(second.isResident(other));
  EXPECT_FALSE(second.isResident(b));
}

TEST(Loader, BackgroundThreadLoadsWhatTheSelectorWantsWithoutTheRenderThreadWaiting) {
  SyntheticCity c;
  c.depth = 3;
  MemoryNodeSource src(makeSyntheticCity(c));
  const Skeleton& sk = src.skeleton();
  // Every read waits on the link, and the link's clock holds the loader thread there until the
  // test lets it go: each frame below runs while the loader thread is parked mid-load, so a frame
  // that waited for the loader would never end.
  auto clock = std::make_shared<GatedLinkClock>();
  LoaderParams p;
  p.chunkBytes = 8192;
  p.ioMbps = 100.0;
  p.ioLatencyMs = 0.2;
  p.clock = clock;
  Loader loader(src, p);
  ASSERT_TRUE(loader.loadRoots().ok());  // on the test's thread: the link's waits pass at once
  clock->close();
  loader.start();
  SelectorParams sp;
  sp.lakhia.vTimeInitial = 1e-8;  // everything fits the budget: residency is the only limit
  LakhiaSelector sel(sk, sp);
  ResidencySet gpu(sk.nodes.size());  // what the render thread has uploaded
  View v;
  v.camera.position = {-60, -60, 80};
  v.camera.target = {100, 100, 0};
  auto idle = [&] { return loader.waitUntilIdle(std::chrono::milliseconds(0)); };
  std::uint32_t firstCoarser = 0, lastCoarser = 0;
  int framesWhileParked = 0, frame = 0;
  for (; frame < 20000; ++frame) {
    const GatedLinkClock::Parked parked = clock->awaitParkedOr(idle);
    ASSERT_NE(parked, GatedLinkClock::Parked::NotWithinAMinute)
        << "the loader thread neither waits on the link nor goes idle";
    // The render thread's frame: take what loaded, select against it, hand on the priorities.
    for (const LoaderEvent& e : loader.drainEvents()) {
      gpu.set(e.node, e.kind == LoaderEvent::Kind::Loaded);
      if (e.kind == LoaderEvent::Kind::Loaded) {
        ASSERT_NE(e.mesh, nullptr);
      }
    }
    const Selection s = sel.select(v, gpu);
    loader.setWanted(s.loadPriorities);
    for (std::uint32_t n : s.front) ASSERT_TRUE(gpu.isResident(n));
    if (parked == GatedLinkClock::Parked::OnTheLink) {
      ++framesWhileParked;
      clock->release();
    }
    if (frame == 0) firstCoarser = s.coarserBecauseNotResident;
    lastCoarser = s.coarserBecauseNotResident;
    if (frame > 0 && lastCoarser == 0) break;
  }
  EXPECT_GT(firstCoarser, 0u);  // the first frames draw coarser than they want
  EXPECT_EQ(lastCoarser, 0u) << "after " << frame << " frames";
  EXPECT_GT(framesWhileParked, 0);
  loader.stop();
  EXPECT_FALSE(loader.running());
}

}  // namespace
}  // namespace hlod
