// Frustum culling that starts at the block quadtree (hlod/runtime/QuadtreeCulling.h): on a
// city of 400 blocks anchored in latitude and longitude, every selector draws the same fronts
// with and without it, frame by frame along the default city's camera paths, while whole cells
// far outside the view are never looked into.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "RuntimeTestScene.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/geodesy/Geodesy.h"
#include "hlod/runtime/CameraPath.h"
#include "hlod/runtime/LakhiaSelector.h"
#include "hlod/runtime/Selector.h"

using namespace hlod;

namespace {

// A synthetic city of blocksX x blocksY blocks at Berkeley, each block anchored at its centre.
Skeleton anchoredCity(int blocks) {
  test::SyntheticCity c;
  c.blocksX = blocks;
  c.blocksY = blocks;
  Skeleton s = test::makeSyntheticCity(c);
  const EnuFrame frame(LatLon{37.87, -122.27, 0.0});
  std::vector<std::optional<LatLon>> anchors;
  for (std::uint32_t r : s.roots) anchors.push_back(frame.toGeodetic(s.nodes[r].bounds.centre()));
  s.quadtree = quadtreeOfRoots(s, anchors);
  return s;
}

std::unique_ptr<Selector> selector(const std::string& name, const Skeleton& s, bool culling) {
  SelectorParams p;
  p.quadtreeCulling = culling;
  p.lakhia.c_targetTime = 20.0;
  p.lakhia.vTimeInitial = 4e-4;  // a frame of ~50 hlod_0 nodes takes 20 ms
  p.ssePixels = 8.0;
  return std::move(*makeSelector(name, s, p));
}

}  // namespace

TEST(QuadtreeCulling, EverySelectorDrawsTheSameFrontsWithAndWithoutItAlongTheCityPaths) {
  const Skeleton s = anchoredCity(20);
  ASSERT_EQ(s.quadtree.domain, QuadtreeDomain::Geographic);
  AllResident all;
  for (const std::string kind : {"walk-fly", "drive", "orbit"}) {
    auto path = makeCameraPath(kind, s);
    ASSERT_TRUE(path.ok()) << path.message();
    const auto samples = path->sampleAt(4.0);
    ASSERT_FALSE(samples.empty());
    for (const std::string name : {"lakhia", "sse", "fs", "full"}) {
      auto with = selector(name, s, true), without = selector(name, s, false);
      std::size_t culledFrames = 0, visitedWith = 0, visitedWithout = 0;
      for (const CameraSample& sample : samples) {
        View view;
        view.camera = sample.camera;
        view.velocity = sample.velocity;
        const Selection a = with->select(view, all), b = without->select(view, all);
        ASSERT_EQ(a.front, b.front) << kind << " " << name << " t " << sample.time;
        EXPECT_EQ(a.upToggles, b.upToggles);
        EXPECT_EQ(a.downToggles, b.downToggles);
        EXPECT_EQ(a.estimatedMs, b.estimatedMs);
        // The same feedback, so that v_time stays the same in both.
        with->feedback(a.estimatedMs * 1.1);
        without->feedback(b.estimatedMs * 1.1);
        visitedWith += a.loadPriorities.size();
        visitedWithout += b.loadPriorities.size();
        if (a.quadtree.cellsCulled > 0) ++culledFrames;
        EXPECT_EQ(b.quadtree.cellsVisited, 0u);
      }
      // Street level sees a part of the city: cells are skipped on most frames and fewer nodes
      // are looked at (the orbit sees the whole city and skips nothing).
      if (kind != "orbit") {
        EXPECT_GT(culledFrames, samples.size() / 2) << kind << " " << name;
        EXPECT_LT(visitedWith, visitedWithout) << kind << " " << name;
      }
      if (name == "lakhia")
        std::printf("[ %s ] %s: nodes looked at per frame %.0f with the quadtree, %.0f without\n",
                    kind.c_str(), name.c_str(), double(visitedWith) / samples.size(),
                    double(visitedWithout) / samples.size());
    }
  }
}

TEST(QuadtreeCulling, FarCellsAreNotVisitedAndTheirRootsAreBeyondTheFalloff) {
  const Skeleton s = anchoredCity(20);
  // At street level in the south-west corner, looking north-east along the first street.
  Camera cam;
  cam.position = {46.0, -6.0, 1.7};
  cam.target = {46.0, 100.0, 1.7};
  cam.fovY = 50.0;
  const Frustum f = cam.frustum();
  QuadtreeCulling culling(s);
  std::vector<std::uint32_t> roots;
  const QuadtreeWalk walk = culling.candidateRoots(f, 1.0, roots);
  EXPECT_GT(walk.cellsCulled, 0u);
  // Cells under a culled one are never tested.
  EXPECT_LT(walk.cellsVisited, s.quadtree.cells.size());
  EXPECT_LT(roots.size(), s.roots.size() * 3 / 4);
  EXPECT_TRUE(std::is_sorted(roots.begin(), roots.end()));
  // Every root left out is outside the frustum by more than its own fall-off: frustumVis 0.
  LakhiaParams params;
  View view;
  view.camera = cam;
  const PriorityModel model(view, params);
  std::vector<std::uint8_t> kept(s.nodes.size(), 0);
  for (std::uint32_t r : roots) kept[r] = 1;
  std::size_t left = 0;
  for (std::uint32_t r : s.roots) {
    if (kept[r]) continue;
    ++left;
    const NodePriority p = model.evaluate(s.nodes[r]);
    EXPECT_FALSE(p.visible) << r;
    EXPECT_EQ(p.frustumVis, 0.0) << r;
  }
  EXPECT_GT(left, 0u);
  // A larger fall-off keeps more; an infinite one keeps every root.
  std::vector<std::uint32_t> wider;
  culling.candidateRoots(f, 4.0, wider);
  EXPECT_GE(wider.size(), roots.size());
  culling.candidateRoots(f, std::numeric_limits<double>::infinity(), wider);
  EXPECT_EQ(wider, s.roots);
}

TEST(QuadtreeCulling, ASkeletonWithoutAQuadtreeVisitsEveryRoot) {
  test::SyntheticCity c;
  const Skeleton s = test::makeSyntheticCity(c);
  ASSERT_TRUE(s.quadtree.empty());
  QuadtreeCulling culling(s);
  Camera cam;
  std::vector<std::uint32_t> roots;
  const QuadtreeWalk walk = culling.candidateRoots(cam.frustum(), 1.0, roots);
  EXPECT_EQ(roots, s.roots);
  EXPECT_EQ(walk.cellsVisited, 0u);
}

TEST(QuadtreeCulling, TheParameterTurnsItOffByName) {
  SelectorParams p;
  ASSERT_TRUE(setSelectorParams(p, "quadtreeCulling=0").ok());
  EXPECT_FALSE(p.quadtreeCulling);
  EXPECT_FALSE(setSelectorParams(p, "quadtreeCulling=0.5").ok());
}
