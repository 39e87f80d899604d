// The object hierarchy of Manocha sec. 2.2 (builder/ObjectHierarchy.h) and its criteria (sec.
// 2.1.1, builder/HierarchyCriteria.h): partitioning, MST clustering and the AABB hierarchy on
// hand-made object sets with known answers, the criteria computed exactly on small trees, and the
// HLODs built bottom up (sec. 2.2.1) checked against the objects they stand for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "BuildTestMeshes.h"
#include "ImportTestUtil.h"
#include "builder/AabbHierarchy.h"
#include "builder/MstClustering.h"
#include "builder/ObjectPartition.h"
#include "hlod/builder/HierarchyCriteria.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/builder/ObjectHierarchy.h"
#include "hlod/metrics/SimplifiedFacing.h"
#include "hlod/metrics/SurfaceDistance.h"
#include "hlod/store/NodeStore.h"

using namespace hlod;

namespace {

Aabb box(glm::dvec3 lo, glm::dvec3 hi) {
  Aabb b;
  b.extend(lo);
  b.extend(hi);
  return b;
}

// An object item: a box, its centre, its triangles.
PartitionItem item(glm::dvec3 lo, glm::dvec3 hi, std::uint64_t triangles = 12) {
  PartitionItem it;
  it.box = box(lo, hi);
  it.centre = it.box.centre();
  it.triangles = triangles;
  return it;
}

// n cubes of side 1 in a row along x from `start`, `gap` apart.
std::vector<PartitionItem> row(glm::dvec3 start, int n, double gap) {
  std::vector<PartitionItem> out;
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 lo = start + glm::dvec3(i * (1.0 + gap), 0, 0);
    out.push_back(item(lo, lo + glm::dvec3(1.0)));
  }
  return out;
}

// Appends `m` to the model as one object.
void addObject(Model& model, Mesh m, glm::vec4 colour) {
  m.baseColor = colour;
  const auto object = std::uint32_t(model.objectCount() - (model.objectRuns.empty() ? 1 : 0));
  model.objectRuns.push_back(
      {object, std::uint32_t(model.meshes.size()), 0, std::uint32_t(m.triangleCount())});
  model.meshes.push_back(std::move(m));
}

// A closed tube along x from x0 to x1 (radius r, n sides, rings every `step`).
Mesh tube(double x0, double x1, double r, int n, double step) {
  Mesh m;
  const int rings = std::max(2, int(std::lround((x1 - x0) / step)) + 1);
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < n; ++j) {
      const double a = 2.0 * M_PI * j / n;
      m.positions.emplace_back(x0 + (x1 - x0) * i / (rings - 1), r * std::cos(a), r * std::sin(a));
    }
  for (int i = 0; i + 1 < rings; ++i)
    for (int j = 0; j < n; ++j) {
      const auto v = [&](int ii, int jj) { return std::uint32_t(ii * n + (jj % n)); };
      m.indices.insert(m.indices.end(), {v(i, j), v(i, j + 1), v(i + 1, j + 1), v(i, j),
                                         v(i + 1, j + 1), v(i + 1, j)});
    }
  return m;
}

}  // namespace

TEST(MstClustering, TwoFarGroupsOfSmallObjectsBecomeTwoClusters) {
  std::vector<PartitionItem> items = row(glm::dvec3(0.0), 10, 0.2);
  const std::vector<PartitionItem> far = row(glm::dvec3(100.0, 0, 0), 10, 0.2);
  items.insert(items.end(), far.begin(), far.end());
  MstClusteringOptions o;
  o.k = 4.0 * std::sqrt(3.0);  // kScale 4 times the cubes' diagonal
  o.maxTriangles = 1000;       // room for both groups: only the FH predicate parts them
  const auto clusters = clusterByMst(items, o);
  ASSERT_EQ(clusters.size(), 2u);
  std::vector<std::uint32_t> first(10), second(10);
  std::iota(first.begin(), first.end(), 0u);
  std::iota(second.begin(), second.end(), 10u);
  EXPECT_EQ(clusters[0], first);
  EXPECT_EQ(clusters[1], second);
}

TEST(MstClustering, MergesAsFelzenszwalbHuttenlocherPredicateSays) {
  // Three cubes on a line, gaps 1 and 3. The first edge (w 1) merges when 1 <= k. The second
  // (w 3) then faces MInt = min(Int 1 + k/2, 0 + k/1): k = 3 gives 2.5 < 3 (apart), k = 5 gives
  // 3.5 >= 3 (merged).
  const std::vector<PartitionItem> items{item({0, 0, 0}, {1, 1, 1}), item({2, 0, 0}, {3, 1, 1}),
                                         item({6, 0, 0}, {7, 1, 1})};
  MstClusteringOptions o;
  o.k = 3.0;
  EXPECT_EQ(clusterByMst(items, o).size(), 2u);
  o.k = 5.0;
  EXPECT_EQ(clusterByMst(items, o).size(), 1u);
  o.k = 0.5;  // not even the first
  EXPECT_EQ(clusterByMst(items, o).size(), 3u);
}

TEST(MstClustering, ClustersStayWithinTheirTriangleBudgetAndTouchingObjectsJoin) {
  const std::vector<PartitionItem> items = row(glm::dvec3(0.0), 12, 0.0);  // touching cubes
  MstClusteringOptions o;
  o.k = 0.0;            // only touching (w 0) edges can merge
  o.maxTriangles = 48;  // four cubes
  const auto clusters = clusterByMst(items, o);
  std::size_t all = 0;
  for (const auto& c : clusters) {
    EXPECT_LE(c.size(), 4u);
    all += c.size();
    // A cluster is a run of neighbours: contiguous in the row.
    for (std::size_t k = 1; k < c.size(); ++k) EXPECT_EQ(c[k], c[k - 1] + 1);
  }
  EXPECT_EQ(all, 12u);
  EXPECT_EQ(clusters.size(), 3u);
}

TEST(ObjectPartition, SplitsALongObjectByItsPolygonsUntilWithinTheLimits) {
  // A tube 100 long: its triangles as items; pieces at most 10 long.
  const Mesh m = tube(0.0, 100.0, 1.0, 8, 1.0);
  std::vector<PartitionItem> polygons;
  for (std::size_t t = 0; t < m.triangleCount(); ++t) {
    PartitionItem p;
    for (int k = 0; k < 3; ++k) p.box.extend(m.positions[m.indices[3 * t + k]]);
    p.centre = p.box.centre();
    polygons.push_back(p);
  }
  const auto groups = partitionTopDown(polygons, {100000, 10.0});
  EXPECT_GE(groups.size(), 10u);
  std::vector<int> seen(polygons.size(), 0);
  for (const auto& g : groups) {
    EXPECT_LE(boxOf(polygons, g).size().x, 10.0);
    for (std::uint32_t i : g) ++seen[i];
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }));
  // By triangles: at most 64 each.
  for (const auto& g : partitionTopDown(polygons, {64, 1e9})) EXPECT_LE(g.size(), 64u);
  // A floor slab's two triangles spanning it all: over the extent, but no split shrinks it.
  std::vector<PartitionItem> slab{item({0, 0, 0}, {50, 0, 50}, 1), item({0, 0, 0}, {50, 0, 50}, 1)};
  slab[1].centre += glm::dvec3(1.0, 0.0, 0.0);
  EXPECT_EQ(partitionTopDown(slab, {100, 10.0}).size(), 1u);
}

TEST(ObjectPartition, AGroupTheHeuristicCannotShrinkIsSplitAcrossItsLongestSide) {
  // Two rows of overlapping strips 30 long, staggered 10 apart along x (0..100), at y 0 and 3.
  // Along y the halves do not overlap, so the heuristic picks y; but each half is still 100 long.
  // Across x the halves shrink, so the group is split there instead of staying whole.
  std::vector<PartitionItem> strips;
  for (double y : {0.0, 3.0})
    for (int i = 0; i < 8; ++i) strips.push_back(item({10.0 * i, y, 0}, {10.0 * i + 30, y + 1, 1}));
  const std::vector<std::uint32_t> all = [&] {
    std::vector<std::uint32_t> v(strips.size());
    std::iota(v.begin(), v.end(), 0u);
    return v;
  }();
  const auto first = splitInTwo(strips, all, SplitAt::CentreOfMass);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->axis, 1);
  const auto across = splitInTwo(strips, all, SplitAt::CentreOfMass, 0);
  ASSERT_TRUE(across);
  EXPECT_EQ(across->axis, 0);
  const auto groups = partitionTopDown(strips, {100000, 60.0});
  EXPECT_GE(groups.size(), 2u);
  for (const auto& g : groups) EXPECT_LE(boxOf(strips, g).size().x, 60.0);
}

TEST(SplitAxis, AFlatGridIsSplitAlongItsLongerSpreadWhenTheAreasTie) {
  // 10 x 4 tiles of 0.1 in the plane z = 0: both axes give halves without overlap and, but for
  // rounding, the same summed area; the tie goes to x, the longer spread.
  std::vector<PartitionItem> tiles;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 10; ++i)
      tiles.push_back(item({0.1 * i, 0.1 * j, 0.0}, {0.1 * (i + 1), 0.1 * (j + 1), 0.0}));
  std::vector<std::uint32_t> all(tiles.size());
  std::iota(all.begin(), all.end(), 0u);
  for (SplitAt at : {SplitAt::CentreOfMass, SplitAt::Median}) {
    const auto s = splitInTwo(tiles, all, at);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->axis, 0);
    EXPECT_EQ(s->lower.size(), 20u);
  }
}

TEST(ObjectHierarchy, OneLongObjectIsSplitAndSmallOnesAreClustered) {
  Model model;
  addObject(model, tube(0.0, 200.0, 1.0, 12, 0.5), glm::vec4(0.2f, 0.6f, 0.2f, 1.0f));
  // Ten small boxes resting on the tube near each end.
  for (int i = 0; i < 10; ++i)
    for (double x : {10.0, 180.0})
      addObject(model, testmesh::box({x + i, 1.0, -0.2}, {x + i + 0.4, 1.4, 0.2}),
                glm::vec4(0.8f, 0.1f, 0.1f, 1.0f));
  ObjectHierarchyOptions o;
  o.maxTriangles = 2000;
  const ObjectHierarchy h = buildObjectHierarchy(model, o);
  EXPECT_EQ(h.inputObjects, 21u);
  EXPECT_GT(h.afterPartition, 21u);  // the tube became sub-objects
  const HierarchyShape shape = shapeOf(h);
  EXPECT_GT(shape.leavesPerObject[0], 1u);
  for (std::uint32_t o2 = 1; o2 < 21; ++o2) EXPECT_EQ(shape.leavesPerObject[o2], 1u);
  // Every triangle in exactly one leaf; each redefined object within the limits.
  std::uint64_t leafTriangles = 0;
  for (const auto& n : h.nodes)
    if (n.childCount == 0) leafTriangles += n.triangles;
  EXPECT_EQ(leafTriangles, model.triangleCount());
  for (const RedefinedObject& r : h.objects) {
    EXPECT_LE(r.triangles, o.maxTriangles);
    const glm::dvec3 s = r.box.size();
    EXPECT_LE(std::max({s.x, s.y, s.z}), h.maxExtent);
  }
  // The small boxes near one end share leaves with each other, never with the other end's.
  for (const RedefinedObject& r : h.objects) {
    bool nearStart = false, nearEnd = false;
    for (const ObjectPiece& p : r.pieces)
      if (p.object > 0) (p.object % 2 == 1 ? nearStart : nearEnd) = true;
    EXPECT_FALSE(nearStart && nearEnd);
  }
}

TEST(AabbHierarchy, FourObjectsInARowMakeABalancedTreeWithoutOverlap) {
  const std::vector<PartitionItem> items = row(glm::dvec3(0.0), 4, 1.0);
  const std::vector<AabbNode> nodes = buildAabbHierarchy(items, 2);
  ASSERT_EQ(nodes.size(), 7u);
  EXPECT_EQ(nodes[0].childCount, 2u);
  // Median split: the two left cubes, then the two right ones.
  EXPECT_EQ(nodes[1].box.max.x, 3.0);
  EXPECT_EQ(nodes[2].box.min.x, 4.0);
  HierarchyShape shape;
  for (const AabbNode& n : nodes)
    shape.nodes.push_back({n.box, n.parent, n.firstChild, n.childCount, n.triangles});
  const HierarchyFigures f = measureHierarchy(shape, 0.0);
  EXPECT_EQ(f.depth, 2u);
  EXPECT_EQ(f.minLeafDepth, 2u);
  EXPECT_EQ(f.balance, 1.0);
  EXPECT_EQ(f.siblingOverlap, 0.0);
  EXPECT_EQ(f.overlappingPairs, 0.0);
  // Fill: the root's box 7 long holds two boxes 3 long (6/7); each pair node's 3 holds 2 (2/3).
  EXPECT_NEAR(f.innerFill, (6.0 / 7.0 + 2.0 / 3.0 + 2.0 / 3.0) / 3.0, 1e-12);
}

TEST(HierarchyCriteria, OverlapBalanceAndFillOfASmallTreeAreExact) {
  // root [0,3]x[0,1]x[0,1]: a leaf A [0,2]... and an inner node B [1,3] with leaves C [1,2], D
  // [2,3] (flat in z: a pad of 0.5 gives them volume).
  HierarchyShape s;
  s.nodes.push_back({box({0, 0, 0}, {3, 1, 1}), 0xffffffffu, 1, 2, 0});
  s.nodes.push_back({box({0, 0, 0}, {2, 1, 1}), 0, 0, 0, 100});
  s.nodes.push_back({box({1, 0, 0}, {3, 1, 1}), 0, 3, 2, 0});
  s.nodes.push_back({box({1, 0, 0.5}, {2, 1, 0.5}), 2, 0, 0, 10});
  s.nodes.push_back({box({2, 0, 0.5}, {3, 1, 0.5}), 2, 0, 0, 30});
  s.leavesPerObject = {1, 2, 0, 1};
  const HierarchyFigures f = measureHierarchy(s, 0.0);
  EXPECT_EQ(f.nodes, 5u);
  EXPECT_EQ(f.leaves, 3u);
  EXPECT_EQ(f.roots, 1u);
  EXPECT_EQ(f.depth, 2u);
  EXPECT_EQ(f.minLeafDepth, 1u);
  EXPECT_DOUBLE_EQ(f.meanLeafDepth, 5.0 / 3.0);
  EXPECT_DOUBLE_EQ(f.balance, 0.5);
  // Root: A and B share [1,2] (volume 1) of the root's 3; B's flat children share nothing.
  EXPECT_DOUBLE_EQ(f.siblingOverlap, (1.0 / 3.0 + 0.0) / 2.0);
  EXPECT_DOUBLE_EQ(f.overlappingPairs, 0.5);
  // Fill: the root is filled (A and B cover [0,3]); B's flat children have no volume (0 of 2).
  EXPECT_DOUBLE_EQ(f.innerFill, (1.0 + 0.0) / 2.0);
  EXPECT_DOUBLE_EQ(f.leavesPerObject, 4.0 / 3.0);  // the object without triangles left out
  EXPECT_DOUBLE_EQ(f.objectsCut, 1.0 / 3.0);
  EXPECT_EQ(f.leafTriangles.min, 10.0);
  EXPECT_EQ(f.leafTriangles.median, 30.0);
  EXPECT_EQ(f.leafTriangles.max, 100.0);
  // With a pad of 0.5 the flat leaves are unit cubes [1,2] and [2,3] (grown to [0.5,2.5] and
  // [1.5,3.5] in x): they share [1.5,2.5] x [-0.5,1.5] x [0,1] = 1 x 2 x 1 of B's padded 3 x 2 x 2.
  const HierarchyFigures p = measureHierarchy(s, 0.5);
  const double rootShare = (2.0 * 2.0 * 2.0) / (4.0 * 2.0 * 2.0);  // [0.5,2.5] of [-0.5,3.5] in x
  EXPECT_DOUBLE_EQ(p.siblingOverlap, (rootShare + 2.0 / 12.0) / 2.0);
  EXPECT_DOUBLE_EQ(p.overlappingPairs, 1.0);
}

TEST(HierarchyCriteria, UnionVolumeCountsSharedSpaceOnce) {
  EXPECT_DOUBLE_EQ(unionVolume({box({0, 0, 0}, {2, 2, 2}), box({1, 1, 1}, {3, 3, 3})}), 15.0);
  EXPECT_DOUBLE_EQ(unionVolume({box({0, 0, 0}, {1, 1, 1}), box({5, 0, 0}, {6, 1, 1})}), 2.0);
  EXPECT_DOUBLE_EQ(unionVolume({box({0, 0, 0}, {4, 4, 4}), box({1, 1, 1}, {2, 2, 2})}), 64.0);
  EXPECT_DOUBLE_EQ(overlapVolume(box({0, 0, 0}, {2, 2, 2}), box({1, 1, 1}, {3, 3, 3})), 1.0);
  EXPECT_DOUBLE_EQ(overlapVolume(box({0, 0, 0}, {1, 1, 1}), box({1, 0, 0}, {2, 1, 1})), 0.0);
}

namespace {

// A model of 24 small objects in two rows (spheres and boxes, two colours).
Model partsModel() {
  Model model;
  for (int i = 0; i < 12; ++i) {
    Mesh s = testmesh::sphere(8, 12, 0.45);
    for (auto& p : s.positions) p += glm::dvec3(i * 1.0, 0.0, 0.0);
    addObject(model, std::move(s), glm::vec4(0.9f, 0.2f, 0.1f, 1.0f));
    addObject(model, testmesh::box({i * 1.0 - 0.4, 1.0, -0.4}, {i * 1.0 + 0.4, 1.6, 0.4}),
              glm::vec4(0.2f, 0.3f, 0.9f, 1.0f));
  }
  return model;
}

Mesh worldMesh(const LocalMesh& m) {
  Mesh out;
  for (const auto& p : m.positions) out.positions.push_back(m.centre + glm::dvec3(p));
  out.indices = m.indices;
  return out;
}

void append(Mesh& dst, const Mesh& src) {
  const auto base = std::uint32_t(dst.positions.size());
  dst.positions.insert(dst.positions.end(), src.positions.begin(), src.positions.end());
  for (std::uint32_t i : src.indices) dst.indices.push_back(base + i);
}

}  // namespace

TEST(ObjectHlods, InnerNodesCoverTheirChildrenWithoutFlippedTriangles) {
  hlod::testing::TempDir dir;
  const Model model = partsModel();
  BuildOptions options;
  options.hierarchy = HierarchyMode::Objects;
  options.minLeafTri = 100;  // redefined objects of at most 300 triangles: a few levels
  options.desiredTri = 16;
  options.threads = 1;
  auto built = buildStoreFromModel(model, dir.file("parts.hlod"), options);
  ASSERT_TRUE(built.ok()) << built.message();
  ASSERT_EQ(built->roots, std::vector<std::uint32_t>{0});
  auto store = NodeStore::open(dir.file("parts.hlod"));
  ASSERT_TRUE(store.ok()) << store.message();
  const Skeleton& s = (*store)->skeleton();
  std::uint64_t leafTriangles = 0;
  std::size_t inner = 0;
  for (std::uint32_t n = 0; n < s.nodes.size(); ++n) {
    const NodeInfo& info = s.nodes[n];
    if (info.childCount == 0) {
      leafTriangles += info.numTri;
      EXPECT_EQ(info.geometricError, 0.0);
      continue;
    }
    ++inner;
    auto hlodMesh = (*store)->loadNode(n);
    ASSERT_TRUE(hlodMesh.ok()) << hlodMesh.message();
    Mesh children;
    for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c) {
      auto child = (*store)->loadNode(c);
      ASSERT_TRUE(child.ok()) << child.message();
      append(children, worldMesh(*child));
      EXPECT_GE(info.geometricError, s.nodes[c].geometricError);  // monotone
      // The node's box holds its children's.
      EXPECT_TRUE(glm::all(glm::lessThanEqual(info.bounds.min, s.nodes[c].bounds.min)));
      EXPECT_TRUE(glm::all(glm::greaterThanEqual(info.bounds.max, s.nodes[c].bounds.max)));
    }
    const Mesh hlod = worldMesh(*hlodMesh);
    EXPECT_LT(hlod.triangleCount(), children.triangleCount()) << "node " << n;
    auto facing = metrics::checkFacing(children, hlod);
    ASSERT_TRUE(facing.ok()) << facing.message();
    EXPECT_EQ(facing->flipped, 0u) << "node " << n;
    // Covers: no sample of the children's surface farther from the HLOD than the node's error
    // (the guard measured it so), with a margin for other samples than the guard's.
    const double diagonal = glm::length(info.bounds.size());
    auto lost =
        metrics::farSamples(children, hlod, 20000, 1.5 * info.geometricError + 1e-3 * diagonal, 7);
    ASSERT_TRUE(lost.ok()) << lost.message();
    EXPECT_TRUE(lost->empty()) << "node " << n << ": " << lost->size() << " samples, the first "
                               << (lost->empty() ? 0.0 : lost->front().distance) << " off; error "
                               << info.geometricError;
  }
  EXPECT_GE(inner, 3u);
  EXPECT_EQ(leafTriangles, model.triangleCount());  // the leaves hold the objects as they are
}

TEST(ObjectHierarchy, AutoPicksObjectsForManyObjectsButNotForCities) {
  Model many = partsModel();
  EXPECT_EQ(resolveHierarchy(HierarchyMode::Auto, many), HierarchyMode::Objects);
  EXPECT_EQ(resolveHierarchy(HierarchyMode::Planes, many), HierarchyMode::Planes);
  Model one;
  one.meshes.push_back(testmesh::sphere(8, 8));
  EXPECT_EQ(resolveHierarchy(HierarchyMode::Auto, one), HierarchyMode::Planes);
  EXPECT_EQ(resolveHierarchy(HierarchyMode::Objects, one), HierarchyMode::Objects);
  many.cityObjects = many.objectCount();
  EXPECT_EQ(resolveHierarchy(HierarchyMode::Auto, many), HierarchyMode::Planes);
}

TEST(ObjectHierarchy, PlaneCutsCutObjectsThatTheObjectHierarchyKeepsWhole) {
  const Model model = partsModel();
  BuildOptions options;
  options.minLeafTri = 100;
  options.desiredTri = 16;
  const HierarchyShape planes = planeCutShape(model, options);
  const HierarchyShape objects =
      shapeOf(buildObjectHierarchy(model, objectHierarchyOptions(options)));
  const HierarchyFigures fp = measureHierarchy(planes, 0.0), fo = measureHierarchy(objects, 0.0);
  EXPECT_EQ(fo.objectsCut, 0.0);  // small objects are never split
  EXPECT_GT(fp.objectsCut, 0.0);  // slabs cut through them
  EXPECT_EQ(fp.roots, 2u);        // one block per colour
  std::uint64_t planeLeafTriangles = 0;
  for (const HierarchyNode& n : planes.nodes)
    if (n.childCount == 0) planeLeafTriangles += n.triangles;
  EXPECT_EQ(planeLeafTriangles, model.triangleCount());
}
