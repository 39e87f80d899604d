// Degenerate trees and models: a node whose visible children are none, a node that costs
// nothing, a node without area (or without bounds), siblings whose priorities sum to zero, a
// model of one triangle, a model of no triangles. Asserts that every selector (lakhia, sse, fs,
// full) gives finite values and a sane front (visible, resident, no node with its ancestor,
// stable under a still camera), and that the builder builds what has triangles and says why it
// builds nothing when there are none.
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "../unit/RuntimeTestScene.h"
#include "HardcaseFolder.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/runtime/LakhiaSelector.h"
#include "hlod/runtime/Loader.h"
#include "hlod/runtime/Selector.h"
#include "hlod/store/NodeStore.h"
#include "service/Session.h"

namespace {

using hlod::NodeInfo;
using hlod::Skeleton;

constexpr const char* kSelectors[] = {"lakhia", "sse", "fs", "full"};

Skeleton withChildren(const hlod::Aabb& rootBox, const std::vector<hlod::Aabb>& childBoxes) {
  Skeleton sk;
  sk.params.desiredTri = 100;
  NodeInfo root;
  root.bounds = rootBox;
  root.centre = rootBox.centre();
  root.numTri = 100;
  root.cost = 100;
  root.staticBenefit = 50;
  root.geometricError = 5;
  root.avgNormal = {0, -1, 0};
  root.firstChild = 1;
  root.childCount = static_cast<std::uint32_t>(childBoxes.size());
  sk.nodes.push_back(root);
  sk.roots.push_back(0);
  for (const hlod::Aabb& b : childBoxes) {
    NodeInfo c = root;
    c.parent = 0;
    c.level = 1;
    c.firstChild = c.childCount = 0;
    c.bounds = b;
    c.centre = b.centre();
    c.staticBenefit = 30;
    c.geometricError = 0;
    sk.nodes.push_back(c);
  }
  return sk;
}

hlod::Aabb box(glm::dvec3 lo, glm::dvec3 hi) {
  hlod::Aabb b;
  b.min = lo;
  b.max = hi;
  return b;
}

// The facade of a 100 m long block (y = 0 plane, facing -y) split in thirds, seen from 30 m.
Skeleton facadeInThirds() {
  return withChildren(
      box({0, 0, 0}, {90, 10, 20}),
      {box({0, 0, 0}, {30, 10, 20}), box({30, 0, 0}, {60, 10, 20}), box({60, 0, 0}, {90, 10, 20})});
}

hlod::View facadeView() {
  hlod::View v;
  v.camera.position = {45, -30, 10};
  v.camera.target = {45, 0, 10};
  return v;
}

struct Frames {
  std::vector<hlod::Selection> selections;
};

// Six frames of a still camera, with a frame time fed back as measured: 1.2x the estimate.
Frames run(const char* name, const Skeleton& sk, const hlod::View& view,
           const hlod::Residency& residency, const hlod::SelectorParams& params = {}) {
  Frames f;
  auto selector = hlod::makeSelector(name, sk, params);
  EXPECT_TRUE(selector.ok());
  if (!selector) return f;
  for (int i = 0; i < 6; ++i) {
    f.selections.push_back((*selector)->select(view, residency));
    const hlod::Selection& s = f.selections.back();
    (*selector)->feedback(s.estimatedMs > 0.0 ? 1.2 * s.estimatedMs : 1.0);
    if (const auto* lakhia = dynamic_cast<const hlod::LakhiaSelector*>(selector->get())) {
      for (std::uint32_t n = 0; n < sk.nodes.size(); ++n) {
        EXPECT_TRUE(std::isfinite(lakhia->hyst(n)));
        EXPECT_LE(std::abs(lakhia->hyst(n)), params.lakhia.c_hystLimit);
        EXPECT_TRUE(std::isfinite(lakhia->timeSlice(n)) && lakhia->timeSlice(n) >= 0.0);
      }
    }
  }
  return f;
}

// Finite values and a sane front: valid, distinct, resident, visible nodes, none with its
// ancestor, the estimate the sum of the front, and the same front once the camera rests.
void expectSane(const Skeleton& sk, const hlod::View& view, const hlod::Residency& res,
                const Frames& f) {
  const hlod::Frustum frustum = view.camera.frustum();
  for (const hlod::Selection& s : f.selections) {
    EXPECT_TRUE(std::isfinite(s.estimatedMs) && s.estimatedMs >= 0.0);
    EXPECT_TRUE(std::isfinite(s.estimatedCost) && s.estimatedCost >= 0.0);
    EXPECT_TRUE(std::isfinite(s.vTime) && s.vTime > 0.0);
    EXPECT_TRUE(std::isfinite(s.drawBudgetMs));
    for (const auto& r : s.loadPriorities)
      EXPECT_TRUE(std::isfinite(r.priority) && r.priority >= 0.0) << r.node;
    std::set<std::uint32_t> front(s.front.begin(), s.front.end());
    EXPECT_EQ(front.size(), s.front.size());
    for (std::uint32_t n : s.front) {
      ASSERT_LT(n, sk.nodes.size());
      EXPECT_TRUE(res.isResident(n));
      EXPECT_TRUE(frustum.intersects(sk.nodes[n].bounds)) << "drew invisible node " << n;
      for (std::uint32_t p = sk.nodes[n].parent; p != hlod::kNoNode; p = sk.nodes[p].parent)
        EXPECT_FALSE(front.count(p));
    }
  }
  // Still camera: no toggling after the first frames.
  ASSERT_GE(f.selections.size(), 6u);
  EXPECT_EQ(f.selections[4].front, f.selections[5].front);
}

TEST(DegenerateTree, ANodeWhoseChildrenAreAllInvisibleIsDrawnAsAtFullDetailWithoutToggling) {
  // The root's box reaches x = 100; its children's cover only x < 30, and the camera looks at
  // x = 80 through a 10 degree field: the root is visible, none of its children is. At full
  // detail nothing is there to draw (a parent's triangles are made of its children's), and every
  // selector, refining for free, comes to that: an empty front, held while the camera rests.
  const Skeleton sk = withChildren(
      box({0, 0, 0}, {100, 10, 20}),
      {box({0, 0, 0}, {10, 10, 20}), box({10, 0, 0}, {20, 10, 20}), box({20, 0, 0}, {30, 10, 20})});
  hlod::View view;
  view.camera.position = {80, -20, 10};
  view.camera.target = {80, 5, 10};
  view.camera.fovY = 10.0;
  const hlod::Frustum frustum = view.camera.frustum();
  ASSERT_TRUE(frustum.intersects(sk.nodes[0].bounds));
  for (std::uint32_t c = 1; c < 4; ++c) ASSERT_FALSE(frustum.intersects(sk.nodes[c].bounds));
  for (const char* name : kSelectors) {
    SCOPED_TRACE(name);
    const Frames f = run(name, sk, view, hlod::AllResident{});
    expectSane(sk, view, hlod::AllResident{}, f);
    // Never an invisible child; from the first frame on, as at full detail.
    for (const auto& s : f.selections) {
      for (std::uint32_t n : s.front) EXPECT_EQ(n, 0u);
      EXPECT_EQ(s.front, f.selections.back().front);
    }
    EXPECT_TRUE(f.selections.back().front.empty());
    EXPECT_EQ(f.selections.back().estimatedCost, 0.0);
  }
}

TEST(DegenerateTree, ANodeThatCostsNothingIsCountedAtTheCostFloor) {
  Skeleton sk = facadeInThirds();
  const std::uint32_t free = 2;  // the middle third, right in front of the camera
  sk.nodes[free].cost = 0.0;
  sk.nodes[free].numTri = 0;
  for (double floor : {1.0, 0.0}) {  // c_minCost: the default, and the least accepted
    hlod::SelectorParams params;
    params.lakhia.c_minCost = floor;
    for (const char* name : kSelectors) {
      SCOPED_TRACE(std::string(name) + " c_minCost " + std::to_string(floor));
      const Frames f = run(name, sk, facadeView(), hlod::AllResident{}, params);
      expectSane(sk, facadeView(), hlod::AllResident{}, f);
      int drawn = 0;
      for (const hlod::Selection& s : f.selections) {
        // The front's estimate: every other node at its cost, the free one at the floor; a floor
        // of 0 still counts it at something above nothing (its priority and timeNeeded finite).
        double others = 0.0;
        bool hasFree = false;
        for (std::uint32_t n : s.front) {
          if (n == free)
            hasFree = true;
          else
            others += sk.nodes[n].cost;
        }
        drawn += hasFree;
        if (!hasFree) {
          EXPECT_DOUBLE_EQ(s.estimatedCost, others);
        } else if (floor > 0.0) {
          EXPECT_DOUBLE_EQ(s.estimatedCost, others + floor);
        } else {
          EXPECT_GT(s.estimatedCost, others);
          EXPECT_NEAR(s.estimatedCost, others, 1e-6);
        }
        EXPECT_DOUBLE_EQ(s.estimatedMs, s.spentMs + s.frontDraws * s.vTime * s.estimatedCost);
      }
      // Nothing stands between the camera and that third at full detail: the reference draws it.
      if (std::string(name) == "full") {
        EXPECT_EQ(drawn, int(f.selections.size()));
      }
    }
    hlod::LakhiaSelector lakhia(sk, params);
    lakhia.select(facadeView(), hlod::AllResident{});
    const double needed = lakhia.timeNeeded(free);
    EXPECT_TRUE(std::isfinite(needed) && needed > 0.0);
    if (floor > 0.0) {
      EXPECT_DOUBLE_EQ(needed, lakhia.vTime() * floor);
    }
    EXPECT_TRUE(std::isfinite(lakhia.priority(free)));
  }
}

TEST(DegenerateTree, ANodeWithoutAreaOrBoundsGetsNoBenefitAndNoNaN) {
  Skeleton sk = facadeInThirds();
  // Child 1: a point (all its triangles collapsed), no benefit, no normal. Child 2: no bounds
  // at all (an empty box, as a node without vertices has).
  sk.nodes[1].bounds = box({15, 5, 10}, {15, 5, 10});
  sk.nodes[1].staticBenefit = 0.0;
  sk.nodes[1].avgNormal = {0, 0, 0};
  sk.nodes[2].bounds = hlod::Aabb{};
  sk.nodes[2].staticBenefit = 0.0;
  for (const char* name : kSelectors) {
    SCOPED_TRACE(name);
    const Frames f = run(name, sk, facadeView(), hlod::AllResident{});
    for (const auto& s : f.selections) {
      EXPECT_TRUE(std::isfinite(s.estimatedMs));
      for (const auto& r : s.loadPriorities) EXPECT_TRUE(std::isfinite(r.priority));
    }
    EXPECT_EQ(f.selections[4].front, f.selections[5].front);
  }
}

TEST(DegenerateTree, SiblingsWhosePrioritiesSumToZeroShareTheirParentsSliceEqually) {
  Skeleton sk = facadeInThirds();
  for (std::uint32_t c = 1; c < 4; ++c) sk.nodes[c].staticBenefit = 0.0;
  for (const char* name : kSelectors) {
    SCOPED_TRACE(name);
    const Frames f = run(name, sk, facadeView(), hlod::AllResident{});
    expectSane(sk, facadeView(), hlod::AllResident{}, f);
  }
  // Lakhia's eq. 4 divides by the sum of the priorities: with none, the slices are equal. The
  // paper's benefit (with benefits from errors, a leaf has its parent's error: not zero).
  hlod::SelectorParams params;
  params.lakhia.c_targetTime = 100.0;
  params.lakhia.c_errorBenefit = 0.0;
  hlod::LakhiaSelector lakhia(sk, params);
  lakhia.setVTime(1e-2);  // root 1 ms, children 1 ms each: 3 ms of 100
  const hlod::Selection s = lakhia.select(facadeView(), hlod::AllResident{});
  for (std::uint32_t c = 1; c < 4; ++c) {
    EXPECT_EQ(lakhia.priority(c), 0.0);
    EXPECT_TRUE(std::isfinite(lakhia.timeSlice(c)));
    EXPECT_DOUBLE_EQ(lakhia.timeSlice(c), lakhia.timeSlice(1));
  }
  EXPECT_GT(lakhia.timeSlice(1), 0.0);
  // Facing away with c_fore = 1 gives zero foreshortening: the same with every benefit zero.
  Skeleton away = facadeInThirds();
  for (auto& n : away.nodes) n.avgNormal = {0, 1, 0};  // the view is +y: facing away
  hlod::SelectorParams facingAway;
  facingAway.lakhia.c_fore = 1.0;
  for (const char* name : kSelectors) {
    SCOPED_TRACE(std::string(name) + " facing away");
    const Frames f = run(name, away, facadeView(), hlod::AllResident{}, facingAway);
    expectSane(away, facadeView(), hlod::AllResident{}, f);
  }
}

TEST(DegenerateTree, AnEmptySkeletonSelectsAnEmptyFront) {
  const Skeleton empty;
  for (const char* name : kSelectors) {
    SCOPED_TRACE(name);
    const Frames f = run(name, empty, facadeView(), hlod::AllResident{});
    for (const auto& s : f.selections) {
      EXPECT_TRUE(s.front.empty());
      EXPECT_TRUE(s.loadPriorities.empty());
      EXPECT_EQ(s.estimatedCost, 0.0);
      EXPECT_TRUE(std::isfinite(s.estimatedMs));
    }
  }
}

class DegenerateModel : public hardcase::Folder {};

hlod::Model oneTriangle(glm::dvec3 c) {
  hlod::Mesh m;
  m.positions = {c + glm::dvec3(-1, 0, -1), c + glm::dvec3(1, 0, -1), c + glm::dvec3(0, 0, 1)};
  m.indices = {0, 1, 2};
  m.baseColor = {1, 0, 0, 1};
  hlod::Model model;
  model.meshes.push_back(m);
  return model;
}

TEST_F(DegenerateModel, ASingleTriangleBuildsOneNodeThatEverySelectorDrawsAndASessionRenders) {
  const auto store = dir / "one.hlod";
  auto built = hlod::buildStoreFromModel(oneTriangle({0, 0, 0}), store, {});
  ASSERT_TRUE(built.ok()) << built.message();
  ASSERT_EQ(built->nodes.size(), 1u);
  EXPECT_EQ(built->nodes[0].numTri, 1u);
  auto opened = hlod::NodeStore::open(store);
  ASSERT_TRUE(opened.ok()) << opened.message();
  const Skeleton& sk = (*opened)->skeleton();
  hlod::View view;
  view.camera.position = {0, -5, 0};
  view.camera.target = {0, 0, 0};
  for (const char* name : kSelectors) {
    SCOPED_TRACE(name);
    const Frames f = run(name, sk, view, hlod::AllResident{});
    expectSane(sk, view, hlod::AllResident{}, f);
    EXPECT_EQ(f.selections.back().front, std::vector<std::uint32_t>{0});
  }
  // Through a session: the triangle fills the middle of the image.
  service::SessionOptions o;
  o.width = 64;
  o.height = 64;
  o.effects.shading = hlod::Shading::Unlit;
  auto session = service::Session::open(store, o);
  ASSERT_TRUE(session.ok()) << session.message();
  hlod::CameraSample sample;
  sample.camera = view.camera;
  sample.camera.aspect = 1.0;
  auto frame = (*session)->renderFrame(sample, hlod::FrameMode::Settled);
  ASSERT_TRUE(frame.ok()) << frame.message();
  EXPECT_EQ(frame->triangles, 1u);
  const hlod::Image img = (*session)->readback();
  const std::uint8_t* centre = &img.pixels[(32 * 64 + 32) * 4];
  EXPECT_GT(centre[0], 200);
  EXPECT_LT(centre[1], 50);
}

TEST_F(DegenerateModel, AModelWithoutTrianglesIsAClearErrorAndWritesNoStore) {
  hlod::Model none;
  hlod::Model emptyMesh;
  emptyMesh.meshes.emplace_back();
  hlod::Model pointsOnly;
  pointsOnly.meshes.emplace_back();
  pointsOnly.meshes.back().positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (const hlod::Model* m : {&none, &emptyMesh, &pointsOnly}) {
    const auto store = dir / "none.hlod";
    auto built = hlod::buildStoreFromModel(*m, store, {});
    ASSERT_FALSE(built.ok());
    EXPECT_NE(built.message().find("no triangles"), std::string::npos) << built.message();
    EXPECT_FALSE(std::filesystem::exists(store));
  }
}

TEST_F(DegenerateModel, TrianglesWithoutAreaBuildAStoreWhoseSelectionIsFinite) {
  // Three collinear points, and a triangle with all three corners on one point: no area, no
  // normal. The builder builds them (or says why); a store it writes selects finitely.
  hlod::Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 5, 5}};
  m.indices = {0, 1, 2, 3, 3, 3};
  hlod::Model model;
  model.meshes.push_back(m);
  const auto store = dir / "flat.hlod";
  auto built = hlod::buildStoreFromModel(model, store, {});
  if (!built.ok()) {
    EXPECT_NE(built.message().find("triangle"), std::string::npos) << built.message();
    return;
  }
  auto opened = hlod::NodeStore::open(store);
  ASSERT_TRUE(opened.ok()) << opened.message();
  const Skeleton& sk = (*opened)->skeleton();
  hlod::View view;
  view.camera.position = {1, -5, 0};
  view.camera.target = {1, 0, 0};
  for (const auto& n : sk.nodes) {
    EXPECT_TRUE(std::isfinite(n.staticBenefit) && n.staticBenefit >= 0.0);
    EXPECT_TRUE(std::isfinite(n.avgNormal.x) && std::isfinite(n.avgNormal.y) &&
                std::isfinite(n.avgNormal.z));
  }
  for (const char* name : kSelectors) {
    SCOPED_TRACE(name);
    const Frames f = run(name, sk, view, hlod::AllResident{});
    for (const auto& s : f.selections) {
      EXPECT_TRUE(std::isfinite(s.estimatedMs));
      for (const auto& r : s.loadPriorities) EXPECT_TRUE(std::isfinite(r.priority));
    }
  }
}

TEST(DegenerateTree, ALoaderOnAnEmptySkeletonHasNothingToDo) {
  hlod::test::MemoryNodeSource source{Skeleton{}};
  hlod::Loader loader(source);
  EXPECT_TRUE(loader.loadRoots().ok());
  const hlod::LoadRequest bogus[] = {{7, 1.0}};  // a node that does not exist is ignored
  loader.setWanted(bogus);
  EXPECT_FALSE(loader.step());
  EXPECT_EQ(loader.counters().residentNodes, 0u);
}

}  // namespace
