// The loader under a memory cap, with a camera that moves from street to street and rests at
// each (realtime frames, a simulated GPU, the loader stepped a few chunks a frame as its thread
// would). Other 3D Tiles runtimes stop loading once their cache is full (of tiles the camera has
// left behind): here the loader must evict what is no longer wanted and keep loading what fits.
// Asserts, for a cap smaller than hlod_0 and for caps smaller than the front the budget wants:
// the resident bytes (with the loads in flight) stay under the cap, the fronts degrade to coarser
// ones but refine at every stop as far as the cap allows, loads keep happening at each new
// place, and the loader comes to rest under a resting camera (no endless evict-and-reload).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../unit/RuntimeTestScene.h"
#include "../unit/SimulatedRenderer.h"
#include "hlod/runtime/FrameDriver.h"
#include "hlod/runtime/Loader.h"
#include "hlod/runtime/Selector.h"

namespace {

using namespace hlod;

constexpr int kStepsPerFrame = 8;  // loader work a frame: 3 nodes (a chunk and a decode each)
constexpr int kDwellFrames = 100;  // frames the camera rests at each place
constexpr int kRestFrames = 10;    // the last frames of a rest: the loader must be idle by then

struct Rig {
  Rig(const Skeleton& sk, std::uint64_t capBytes) : source(sk) {
    renderer = std::make_unique<test::SimulatedRenderer>(sk.nodes.size());
    renderer->setTriangles(source.skeleton());
    LoaderParams lp;
    lp.capBytes = capBytes;
    loader = std::make_unique<Loader>(source, lp);
    SelectorParams p;
    p.lakhia.c_targetTime = 33.0;
    FrameDriverOptions o;
    o.width = 640;
    o.height = 360;
    o.loaderThread = false;
    o.uploadBudgetMs = 8.0;  // 8 uploads a frame: as many as the loader loads
    driver = std::make_unique<FrameDriver>(std::move(*makeSelector("lakhia", source.skeleton(), p)),
                                           nullptr, *loader, *renderer, o);
  }
  test::MemoryNodeSource source;
  std::unique_ptr<test::SimulatedRenderer> renderer;
  std::unique_ptr<Loader> loader;
  std::unique_ptr<FrameDriver> driver;
};

// Street-level views along the rows of the synthetic city (blocks 40 m, streets 12 m), one
// looking back, and one from above: each wants nodes the others do not.
std::vector<CameraSample> places() {
  std::vector<CameraSample> p;
  auto at = [&](glm::dvec3 eye, glm::dvec3 target) {
    CameraSample s;
    s.camera.position = eye;
    s.camera.target = target;
    p.push_back(s);
  };
  at({-5, 46, 1.7}, {100, 46, 5});
  at({210, 150, 1.7}, {100, 150, 5});
  at({46, -5, 1.7}, {46, 100, 5});
  at({100, -60, 60}, {100, 60, 0});
  at({150, 210, 1.7}, {150, 100, 5});
  return p;
}

std::uint64_t hlod0Bytes(const Skeleton& sk) {
  std::uint64_t b = 0;
  for (std::uint32_t r : sk.roots) b += sk.nodes[r].memoryBytes;
  return b;
}

struct Stop {
  std::uint64_t loadsFinished = 0;  // during the stop
  std::uint64_t unloadsAtRest = 0;  // during its last kRestFrames
  std::uint64_t loadsAtRest = 0;
  std::uint64_t deeperThanHlod0 = 0;  // nodes below hlod_0 in its last frame
  std::uint64_t triangles = 0;        // of its last frame
  std::uint64_t frontBytes = 0;       // memory of its last front and their ancestors
};

struct Journey {
  std::vector<Stop> stops;
  std::uint64_t peakBytes = 0;    // of resident + in flight, sampled after every step
  std::uint64_t maxResident = 0;  // residentBytes after each frame
  bool rootsExceedCap = false;
  bool drewOnlyResident = true;
};

// Cycles twice through the places, resting kDwellFrames at each.
Journey drive(Rig& rig) {
  Journey out;
  EXPECT_TRUE(rig.driver->start().ok());
  const Skeleton& sk = rig.source.skeleton();
  const auto cams = places();
  for (int cycle = 0; cycle < 2; ++cycle) {
    for (const CameraSample& cam : cams) {
      Stop stop;
      const LoaderCounters before = rig.loader->counters();
      LoaderCounters restStart = before;
      for (int f = 0; f < kDwellFrames; ++f) {
        if (f == kDwellFrames - kRestFrames) restStart = rig.loader->counters();
        auto r = rig.driver->renderFrame(cam, FrameMode::Realtime);
        EXPECT_TRUE(r.ok()) << r.message();  // drawing a node not on the GPU is an Error
        if (!r) {
          out.drewOnlyResident = false;
          return out;
        }
        for (int s = 0; s < kStepsPerFrame && rig.loader->step(); ++s) {
          const LoaderCounters c = rig.loader->counters();
          out.peakBytes = std::max(out.peakBytes, c.residentBytes + c.inFlightBytes);
        }
        out.maxResident = std::max(out.maxResident, rig.loader->counters().residentBytes);
        if (f == kDwellFrames - 1) {
          for (std::size_t l = 1; l < r->nodesPerLevel.size(); ++l)
            stop.deeperThanHlod0 += r->nodesPerLevel[l];
          stop.triangles = r->triangles;
          std::vector<std::uint8_t> counted(sk.nodes.size(), 0);
          for (std::uint32_t n : rig.driver->lastFront())
            for (std::uint32_t a = n; a != kNoNode && !counted[a]; a = sk.nodes[a].parent) {
              counted[a] = 1;
              stop.frontBytes += sk.nodes[a].memoryBytes;
            }
        }
      }
      const LoaderCounters after = rig.loader->counters();
      stop.loadsFinished = after.loadsFinished - before.loadsFinished;
      stop.loadsAtRest = after.loadsFinished - restStart.loadsFinished;
      stop.unloadsAtRest = after.unloads - restStart.unloads;
      out.stops.push_back(stop);
      out.rootsExceedCap = after.rootsExceedCap;
    }
  }
  return out;
}

Skeleton city() {
  test::SyntheticCity c;
  c.depth = 4;
  c.triPerNode = 1000;  // 96 KB decoded a node; hlod_0 1.5 MB
  return test::makeSyntheticCity(c);
}

TEST(MemoryCap, ACapSmallerThanHlod0DrawsHlod0AndLoadsNothingElse) {
  const Skeleton sk = city();
  Rig rig(sk, hlod0Bytes(sk) / 2);
  const Journey r = drive(rig);
  ASSERT_EQ(r.stops.size(), 2 * places().size());
  EXPECT_TRUE(r.rootsExceedCap);
  EXPECT_TRUE(r.drewOnlyResident);
  EXPECT_EQ(r.maxResident, hlod0Bytes(sk));  // hlod_0, and nothing on top of it
  for (const Stop& s : r.stops) {
    EXPECT_EQ(s.loadsFinished, 0u);
    EXPECT_EQ(s.deeperThanHlod0, 0u);
    EXPECT_GT(s.triangles, 0u);  // hlod_0 is drawn
  }
  // The loader rests: with nothing that fits, a step finds nothing to do.
  EXPECT_FALSE(rig.loader->step());
}

TEST(MemoryCap, CapsSmallerThanTheBudgetsFrontDegradeToCoarserFrontsAndKeepLoading) {
  const Skeleton sk = city();
  const std::uint64_t roots = hlod0Bytes(sk);
  // What the budget wants without a cap, at each stop: its fronts and their ancestors.
  Rig free(sk, 0);
  const Journey uncapped = drive(free);
  std::uint64_t wanted = 0;
  for (const Stop& s : uncapped.stops) wanted = std::max(wanted, s.frontBytes);
  ASSERT_GT(wanted, roots + 10 * sk.nodes[sk.roots[0]].memoryBytes);
  for (double share : {0.5, 0.25, 0.1}) {
    const std::uint64_t cap = roots + static_cast<std::uint64_t>(share * double(wanted - roots));
    SCOPED_TRACE("cap " + std::to_string(cap) + " bytes: hlod_0 and " + std::to_string(share) +
                 " of the rest the budget wants");
    Rig rig(sk, cap);
    const Journey r = drive(rig);
    ASSERT_EQ(r.stops.size(), uncapped.stops.size());
    EXPECT_FALSE(r.rootsExceedCap);
    EXPECT_TRUE(r.drewOnlyResident);
    EXPECT_LE(r.peakBytes, cap);
    for (std::size_t i = 0; i < r.stops.size(); ++i) {
      const Stop& s = r.stops[i];
      SCOPED_TRACE("stop " + std::to_string(i));
      // Loads happen at every new place, though the cache is full of the last one's nodes...
      EXPECT_GT(s.loadsFinished, 0u);
      // ...the front refines below hlod_0 as far as the cap allows, never finer than without it...
      EXPECT_GT(s.deeperThanHlod0, 0u);
      EXPECT_LE(s.triangles, uncapped.stops[i].triangles);
      EXPECT_LE(s.frontBytes, cap);
      // ...and a resting camera brings the loader to rest: no evict-and-reload cycle.
      EXPECT_EQ(s.loadsAtRest, 0u);
      EXPECT_EQ(s.unloadsAtRest, 0u);
    }
  }
}

TEST(MemoryCap, UnderAStillCameraATightCapComesToRest) {
  // One block, two levels below hlod_0, caps of room for 3 to 8 nodes below it. Before the fix
  // a grandchild near the camera evicted a farther sibling of its parent, which broke the group
  // it needed; the group's subtree, no longer wanted, went in turn for that sibling: one load and
  // one unload a frame, forever (in 12 of these 36 cases).
  test::SyntheticCity c;
  c.blocksX = c.blocksY = 1;
  c.depth = 2;
  const Skeleton sk = test::makeSyntheticCity(c);
  for (int slots = 3; slots <= 8; ++slots) {
    for (double x : {-10.0, 0.0, 7.0, 20.0, 33.0, 50.0}) {
      SCOPED_TRACE("room for " + std::to_string(slots) + " nodes, camera at x " +
                   std::to_string(x));
      Rig rig(sk, hlod0Bytes(sk) + slots * sk.nodes[1].memoryBytes);
      ASSERT_TRUE(rig.driver->start().ok());
      CameraSample cam;
      cam.camera.position = {x, -15, 1.7};
      cam.camera.target = {20, 20, 5};
      LoaderCounters late;
      FrameRecord last;
      for (int f = 0; f < 100; ++f) {
        if (f == 50) late = rig.loader->counters();
        auto r = rig.driver->renderFrame(cam, FrameMode::Realtime);
        ASSERT_TRUE(r.ok()) << r.message();
        last = *r;
        for (int s = 0; s < kStepsPerFrame && rig.loader->step(); ++s) {
        }
      }
      const LoaderCounters end = rig.loader->counters();
      EXPECT_EQ(end.loadsFinished, late.loadsFinished);
      EXPECT_EQ(end.unloads, late.unloads);
      EXPECT_LE(end.peakBytes, hlod0Bytes(sk) + slots * sk.nodes[1].memoryBytes);
      ASSERT_GE(last.nodesPerLevel.size(), 2u);
      EXPECT_GT(last.nodesPerLevel[1] + (last.nodesPerLevel.size() > 2 ? last.nodesPerLevel[2] : 0),
                0u);  // refined below hlod_0: the three children fit
    }
  }
}

// A hand-made tree for the cases below: nodes of 100 triangles, `memory` decoded bytes each.
struct TreeBuilder {
  Skeleton sk;
  std::uint64_t offset = 0;
  std::uint32_t add(const Aabb& box, std::uint32_t parent, std::uint64_t memory) {
    NodeInfo n;
    n.parent = parent;
    n.level = parent == kNoNode ? 0 : sk.nodes[parent].level + 1;
    n.block =
        parent == kNoNode ? static_cast<std::uint32_t>(sk.roots.size()) : sk.nodes[parent].block;
    n.bounds = box;
    n.centre = box.centre();
    n.numTri = 100;
    n.cost = 100;
    const glm::dvec3 s = box.size();
    n.staticBenefit = std::sqrt(100.0 * (2.0 * (s.x * s.z + s.y * s.z) + s.x * s.y));
    n.avgNormal = {0, -1, 0};
    n.payloadSize = 1000;
    n.payloadOffset = offset;
    offset += n.payloadSize;
    n.memoryBytes = memory;
    const auto id = static_cast<std::uint32_t>(sk.nodes.size());
    if (parent == kNoNode) {
      sk.roots.push_back(id);
    } else {
      if (sk.nodes[parent].childCount == 0) sk.nodes[parent].firstChild = id;
      ++sk.nodes[parent].childCount;
    }
    sk.nodes.push_back(n);
    return id;
  }
  // Children of `parent` cutting its box in `count` equal slabs along `axis`.
  std::uint32_t split(std::uint32_t parent, int axis, int count, std::uint64_t memory) {
    const Aabb box = sk.nodes[parent].bounds;
    std::uint32_t first = 0;
    for (int k = 0; k < count; ++k) {
      Aabb piece = box;
      piece.min[axis] = box.min[axis] + (box.max[axis] - box.min[axis]) * k / count;
      piece.max[axis] = box.min[axis] + (box.max[axis] - box.min[axis]) * (k + 1) / count;
      const std::uint32_t id = add(piece, parent, memory);
      if (k == 0) first = id;
    }
    return first;
  }
};

Aabb boxOf(glm::dvec3 lo, glm::dvec3 hi) {
  Aabb b;
  b.min = lo;
  b.max = hi;
  return b;
}

CameraSample looking(glm::dvec3 eye, glm::dvec3 target) {
  CameraSample s;
  s.camera.position = eye;
  s.camera.target = target;
  return s;
}

// Frames of a still camera with kStepsPerFrame loader steps each; the last frame's front.
std::vector<std::uint32_t> rest(Rig& rig, const CameraSample& cam, int frames) {
  for (int f = 0; f < frames; ++f) {
    auto r = rig.driver->renderFrame(cam, FrameMode::Realtime);
    EXPECT_TRUE(r.ok()) << r.message();
    for (int s = 0; s < kStepsPerFrame && rig.loader->step(); ++s) {
    }
  }
  return rig.driver->lastFront();
}

bool contains(const std::vector<std::uint32_t>& v, std::uint32_t n) {
  return std::find(v.begin(), v.end(), n) != v.end();
}

TEST(MemoryCap, ANodeLargerThanTheCachesLeavesEvictsTheChainTheCameraLeftBehind) {
  // Block A: three children, the middle one refined, its middle child refined again: nine
  // nodes of 10 kB in a chain three deep, of which seven have no resident child. Block B: two
  // children of 80 kB and 10 kB. The cap holds hlod_0 and A's nine nodes exactly.
  constexpr std::uint64_t kUnit = 10000;
  TreeBuilder t;
  const std::uint32_t ra = t.add(boxOf({0, 0, 0}, {40, 40, 20}), kNoNode, kUnit);
  const std::uint32_t rb = t.add(boxOf({200, 0, 0}, {240, 40, 20}), kNoNode, kUnit);
  const std::uint32_t a = t.split(ra, 0, 3, kUnit);
  const std::uint32_t c = t.add(boxOf({200, 0, 0}, {220, 40, 20}), rb, 8 * kUnit);
  t.add(boxOf({220, 0, 0}, {240, 40, 20}), rb, kUnit);
  const std::uint32_t b = t.split(a + 1, 1, 3, kUnit);
  const std::uint32_t d = t.split(b + 1, 0, 3, kUnit);
  Rig rig(t.sk, 11 * kUnit);
  ASSERT_TRUE(rig.driver->start().ok());
  // Close to A: all of it loads, and the front reaches its third level.
  const auto nearA = rest(rig, looking({20, -15, 10}, {20, 20, 10}), 60);
  for (std::uint32_t n = a; n < d + 3; ++n)
    if (n != c && n != c + 1) {
      EXPECT_TRUE(rig.loader->isResident(n)) << n;
    }
  EXPECT_TRUE(contains(nearA, d));
  // Then at B, A out of view: B's 80 kB child needs the whole chain gone, not only its leaves.
  const auto nearB = rest(rig, looking({220, -15, 10}, {220, 20, 10}), 60);
  EXPECT_TRUE(rig.loader->isResident(c));
  EXPECT_TRUE(rig.loader->isResident(c + 1));
  EXPECT_TRUE(contains(nearB, c));
  EXPECT_TRUE(contains(nearB, c + 1));
  EXPECT_LE(rig.loader->counters().peakBytes, 11 * kUnit);
}

TEST(MemoryCap, NodesThatCanNeverFitDoNotHoldUpTheOnesThatDo) {
  // Blocks A and B near the camera, each cut in three nodes too large for what hlod_0 leaves of
  // the cap (60 kB and 120 kB, 50 kB left): the six most important wanted nodes. Block C, behind
  // them, has children of 10 kB. Before the fix the loader gave up after four nodes that did not
  // fit, every frame, and C's children never loaded.
  constexpr std::uint64_t kUnit = 10000;
  TreeBuilder t;
  const std::uint32_t ra = t.add(boxOf({0, 0, 0}, {40, 10, 20}), kNoNode, kUnit);
  const std::uint32_t rb = t.add(boxOf({50, 0, 0}, {90, 10, 20}), kNoNode, kUnit);
  const std::uint32_t rc = t.add(boxOf({0, 200, 0}, {90, 210, 20}), kNoNode, kUnit);
  const std::uint32_t a = t.split(ra, 0, 3, 6 * kUnit);
  const std::uint32_t b = t.split(rb, 0, 3, 12 * kUnit);
  const std::uint32_t c = t.split(rc, 0, 3, kUnit);
  const std::uint64_t cap = 8 * kUnit;
  Rig rig(t.sk, cap);
  ASSERT_TRUE(rig.driver->start().ok());
  const auto front = rest(rig, looking({45, -40, 10}, {45, 100, 5}), 40);
  for (std::uint32_t n = c; n < c + 3; ++n) {
    EXPECT_TRUE(rig.loader->isResident(n)) << n;
    EXPECT_TRUE(contains(front, n)) << n;
  }
  for (std::uint32_t n : {a, a + 1, a + 2, b, b + 1, b + 2})
    EXPECT_FALSE(rig.loader->isResident(n));
  EXPECT_LE(rig.loader->counters().peakBytes, cap);
}

}  // namespace
