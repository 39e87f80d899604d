// The HLOD builder (Lakhia III-A/B) on hand-built meshes: equations 1-3, the slab partition, the
// hierarchy's shape, watertight fronts and the simplifiers' contract.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <set>

#include "BuildTestMeshes.h"
#include "builder/ImageResize.h"
#include "builder/Preprocess.h"
#include "builder/SlabPartition.h"
#include "builder/TextureCrop.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/builder/Simplifier.h"

using namespace hlod;

namespace {

bool finite(const glm::dvec3& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

struct PosKey {
  glm::dvec3 p;
  bool operator<(const PosKey& o) const { return std::memcmp(&p, &o.p, sizeof p) < 0; }
  bool operator==(const PosKey& o) const { return std::memcmp(&p, &o.p, sizeof p) == 0; }
};

// Edges (by position, either direction) that exactly one triangle of the front's meshes uses. The
// union of a front of a closed mesh has none: a crack or a T-junction between two of its nodes
// leaves some (a coarse edge a-b beside a fine a-m, m-b leaves all three). Triangles with a
// repeated position are skipped.
std::size_t openEdges(const std::vector<const Mesh*>& front) {
  std::map<std::pair<PosKey, PosKey>, int> uses;
  for (const Mesh* m : front)
    for (std::size_t t = 0; t + 2 < m->indices.size(); t += 3) {
      PosKey p[3];
      for (int k = 0; k < 3; ++k) p[k] = {m->positions[m->indices[t + k]] + glm::dvec3(0.0)};
      if (p[0] == p[1] || p[1] == p[2] || p[0] == p[2]) continue;
      for (int k = 0; k < 3; ++k) {
        PosKey a = p[k], b = p[(k + 1) % 3];
        if (b < a) std::swap(a, b);
        ++uses[{a, b}];
      }
    }
  std::size_t open = 0;
  for (const auto& [edge, n] : uses) open += n == 1;
  return open;
}

// The fronts a selector can draw from one block's nodes: per level L, its nodes and the leaves
// above it; and each of those with one node of level L replaced by its children.
std::vector<std::vector<const Mesh*>> frontsOf(const std::vector<BlockNode>& nodes) {
  std::uint32_t depth = 0;
  for (const BlockNode& n : nodes) depth = std::max(depth, n.info.level);
  std::vector<std::vector<const Mesh*>> fronts;
  for (std::uint32_t level = 0; level <= depth; ++level) {
    std::vector<std::size_t> members;
    for (std::size_t i = 0; i < nodes.size(); ++i)
      if (nodes[i].info.level == level ||
          (nodes[i].info.childCount == 0 && nodes[i].info.level < level))
        members.push_back(i);
    std::vector<const Mesh*> front;
    for (std::size_t i : members) front.push_back(&nodes[i].mesh);
    fronts.push_back(front);
    for (std::size_t i : members) {
      if (nodes[i].info.level != level || nodes[i].info.childCount == 0) continue;
      std::vector<const Mesh*> refined;
      for (std::size_t j : members)
        if (j != i) refined.push_back(&nodes[j].mesh);
      for (std::uint32_t c = 0; c < nodes[i].info.childCount; ++c)
        refined.push_back(&nodes[nodes[i].info.firstChild + c].mesh);
      fronts.push_back(refined);
    }
  }
  return fronts;
}

// The triangles of a mesh as sorted corner positions, sorted: equal for two meshes with the same
// triangles whatever their vertex order.
std::vector<std::array<PosKey, 3>> triangleSet(const std::vector<const Mesh*>& meshes) {
  std::vector<std::array<PosKey, 3>> out;
  for (const Mesh* m : meshes)
    for (std::size_t t = 0; t + 2 < m->indices.size(); t += 3) {
      std::array<PosKey, 3> tri;
      for (int k = 0; k < 3; ++k) tri[k] = {m->positions[m->indices[t + k]] + glm::dvec3(0.0)};
      std::sort(tri.begin(), tri.end());
      out.push_back(tri);
    }
  std::sort(out.begin(), out.end());
  return out;
}

// The leaves under node i (its original triangles).
std::vector<const Mesh*> leavesUnder(const std::vector<BlockNode>& nodes, std::size_t i) {
  std::vector<const Mesh*> out;
  std::vector<std::size_t> stack = {i};
  while (!stack.empty()) {
    const BlockNode& n = nodes[stack.back()];
    stack.pop_back();
    if (n.info.childCount == 0) out.push_back(&n.mesh);
    for (std::uint32_t c = 0; c < n.info.childCount; ++c) stack.push_back(n.info.firstChild + c);
  }
  return out;
}

std::vector<const Mesh*> leavesOf(const std::vector<BlockNode>& nodes) {
  std::vector<const Mesh*> out;
  for (const BlockNode& n : nodes)
    if (n.info.childCount == 0) out.push_back(&n.mesh);
  return out;
}

Mesh triangles(std::vector<glm::dvec3> corners) {
  Mesh m;
  m.positions = std::move(corners);
  for (std::uint32_t i = 0; i < m.positions.size(); ++i) m.indices.push_back(i);
  return m;
}

}  // namespace

TEST(BuildPreprocess, CostIsEquationOne) {
  EXPECT_DOUBLE_EQ(nodeCost(10, 5, 0.6), 10 * 0.6 + 5 * 0.4);
  EXPECT_DOUBLE_EQ(nodeCost(0, 7, 0.25), 7 * 0.75);
}

TEST(BuildPreprocess, TwoKnownTrianglesGiveEquationsOneToThreeExactly) {
  // Triangle A: in the XY plane, area 2, normal +Z. Triangle B: in the XZ plane, area 1, normal -Y.
  Mesh m = triangles({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 0}, {1, 0, 0}, {1, 0, 2}});
  m.texCoords.assign(6, glm::vec2(0.5f));
  m.texture = testmesh::checkerTexture(8, 8);
  const NodeMeasures n = measureNode(m, 0.6);
  EXPECT_EQ(n.numTri, 2u);
  EXPECT_EQ(n.numTexTri, 2u);
  EXPECT_DOUBLE_EQ(n.area, 3.0);
  EXPECT_DOUBLE_EQ(n.cost, 2 * 0.6);
  EXPECT_DOUBLE_EQ(n.staticBenefit, std::sqrt(2.0 * 3.0));
  const glm::dvec3 expected = glm::normalize(glm::dvec3(0, -1, 2));
  EXPECT_NEAR(n.avgNormal.x, expected.x, 1e-7);
  EXPECT_NEAR(n.avgNormal.y, expected.y, 1e-7);
  EXPECT_NEAR(n.avgNormal.z, expected.z, 1e-7);
  EXPECT_EQ(n.bounds.min, glm::dvec3(0, 0, 0));
  EXPECT_EQ(n.bounds.max, glm::dvec3(2, 2, 2));
  // Untextured: every triangle counts with weight 1 - c_tex.
  m.texture = nullptr;
  EXPECT_DOUBLE_EQ(measureNode(m, 0.6).cost, 2 * 0.4);
}

TEST(BuildPreprocess, NodeWithoutAreaGetsPlusZNormalNeverNaN) {
  const glm::vec3 plusZ(0, 0, 1);
  EXPECT_EQ(averageNormal(Mesh{}), plusZ);
  EXPECT_EQ(averageNormal(triangles({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}})), plusZ);  // collinear
  EXPECT_EQ(averageNormal(triangles({{1, 1, 1}, {1, 1, 1}, {1, 1, 1}})), plusZ);  // a point
  // Two opposite faces cancel out.
  EXPECT_EQ(
      averageNormal(triangles({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {0, 1, 0}, {1, 0, 0}})),
      plusZ);
  const NodeMeasures n = measureNode(triangles({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}), 0.5);
  EXPECT_EQ(n.staticBenefit, 0.0);
  EXPECT_EQ(n.avgNormal, plusZ);
}

TEST(BuildPreprocess, ZeroAreaTrianglesAddNothingToTheNormal) {
  Mesh m = triangles({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}, {6, 6, 6}, {7, 7, 7}});
  EXPECT_EQ(averageNormal(m), glm::vec3(0, 0, 1));
  m = triangles({{0, 0, 0}, {0, 1, 0}, {0, 0, 1}, {5, 5, 5}, {6, 6, 6}, {7, 7, 7}});
  EXPECT_EQ(averageNormal(m), glm::vec3(1, 0, 0));
}

// Triangles with a vertex exactly on a plane, an edge lying in it, one thinner than float epsilon
// and one across it: each goes whole, with its vertices' bits, to the slab of its centroid.
TEST(BuildSlabPartition, EveryTriangleGoesWholeToTheSlabOfItsCentroid) {
  const Mesh m = triangles({{-0.5, 0, 0},
                            {0, 1, 0},
                            {0.5, 0, 0},  // centroid x 0
                            {1, 0, 0},
                            {1, 1, 0},
                            {1.2, 0.5, 0},  // edge in the plane x = 1
                            {1, 0, 0},
                            {0.5, 1, 0},
                            {1.5, 0, 0},  // centroid on it
                            {2, 0, 0},
                            {2 + 1e-9, 1, 0},
                            {2 - 1e-9, 2, 0},  // a sliver at x = 2
                            {0.8, 0, 0},
                            {2.9, 0.5, 0},
                            {2.8, 1, 0},  // across both planes
                            {3, 0, 0},
                            {3, 1, 0},
                            {3, 0, 1}});  // centroid x 3
  const SlabPartition p = partitionIntoSlabs(m, 3);
  EXPECT_EQ(p.axis, 0);  // the centroids spread along x, over [0, 3]
  EXPECT_EQ(p.planes, (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(p.triangles[0], (std::vector<std::uint32_t>{0, 2}));  // on a plane: the slab below
  std::vector<int> slabOf(m.triangleCount(), -1);
  for (int k = 0; k < 3; ++k)
    for (std::uint32_t t : p.triangles[std::size_t(k)]) {
      EXPECT_EQ(slabOf[t], -1) << "triangle " << t << " in two slabs";
      slabOf[t] = k;
    }
  for (std::size_t t = 0; t < m.triangleCount(); ++t) {
    ASSERT_NE(slabOf[t], -1) << "triangle " << t << " in no slab";
    const double c = centroid(m, t).x;
    const int expected = c <= p.planes[0] ? 0 : c <= p.planes[1] ? 1 : 2;
    EXPECT_EQ(slabOf[t], expected) << "triangle " << t;
  }
  // A piece holds the triangles bit for bit: no vertex is made, none is moved.
  const Mesh piece = subMesh(m, p.triangles[1]);
  for (const auto& q : piece.positions) {
    EXPECT_TRUE(finite(q));
    EXPECT_NE(std::find(m.positions.begin(), m.positions.end(), q), m.positions.end());
  }
  EXPECT_EQ(piece.triangleCount(), p.triangles[1].size());
}

// A slab too small for a node joins its smaller neighbour, losing the plane between them.
TEST(BuildSlabPartition, SmallSlabsJoinTheirSmallerNeighbour) {
  SlabPartition p;
  p.planes = {1.0, 2.0, 3.0};
  const auto run = [](std::uint32_t from, std::size_t n) {
    std::vector<std::uint32_t> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = from + std::uint32_t(i);
    return v;
  };
  p.triangles = {run(0, 5), run(100, 100), run(300, 2), run(400, 40)};
  mergeSmallSlabs(p, 10);
  // 2 joins 40 (its smaller neighbour), then 5 joins 100 (its only one).
  EXPECT_EQ(p.planes, (std::vector<double>{2.0}));
  ASSERT_EQ(p.triangles.size(), 2u);
  EXPECT_EQ(p.triangles[0].size(), 105u);
  EXPECT_EQ(p.triangles[1].size(), 42u);
  EXPECT_EQ(p.triangles[1].front(), 300u);
  // Empty slabs count as small; a single slab is left alone.
  p.planes = {1.0, 2.0};
  p.triangles = {{}, run(0, 3), {}};
  mergeSmallSlabs(p, 10);
  EXPECT_TRUE(p.planes.empty());
  ASSERT_EQ(p.triangles.size(), 1u);
  EXPECT_EQ(p.triangles[0].size(), 3u);
}

class BuildHierarchy : public testing::TestWithParam<const char*> {};

TEST_P(BuildHierarchy, ChildrenPartitionTheirParentsRegion) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  BuildOptions o;
  o.desiredTri = 200;
  o.minLeafTri = 100;
  const auto nodes = buildBlockHierarchy(testmesh::wavyGrid(60), o, **simplifier);
  ASSERT_GT(nodes.size(), 13u);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const BlockNode& n = nodes[i];
    if (n.info.childCount == 0) continue;
    ASSERT_EQ(n.cutPlanes.size() + 1, n.info.childCount);
    const int a = n.cutAxis;
    for (std::uint32_t c = 0; c < n.info.childCount; ++c) {
      const BlockNode& child = nodes[n.info.firstChild + c];
      EXPECT_EQ(child.info.parent, i);
      EXPECT_EQ(child.info.level, n.info.level + 1);
      for (int k = 0; k < 3; ++k) {
        EXPECT_GE(child.info.bounds.min[k], n.info.bounds.min[k]);
        EXPECT_LE(child.info.bounds.max[k], n.info.bounds.max[k]);
      }
      // Every original triangle under the child has its centroid in one slab, the child's; the
      // children follow the slabs' order.
      std::set<int> slabs;
      for (const Mesh* leaf : leavesUnder(nodes, n.info.firstChild + c))
        for (std::size_t t = 0; t < leaf->triangleCount(); ++t) {
          const double x = centroid(*leaf, t)[a];
          slabs.insert(int(std::lower_bound(n.cutPlanes.begin(), n.cutPlanes.end(), x) -
                           n.cutPlanes.begin()));
        }
      ASSERT_EQ(slabs.size(), 1u) << "node " << i << " child " << c;
      EXPECT_EQ(*slabs.begin(), int(c));
    }
  }
}

TEST_P(BuildHierarchy, TriangleCountsFollowTheSimplificationFactors) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  BuildOptions o;
  o.desiredTri = 500;
  o.minLeafTri = 500;
#ifdef HLODR_SANITIZE_BUILD
  const Mesh block = testmesh::sphere(80, 100);  // 16k triangles: the sanitizers are 4-15x slower
#else
  const Mesh block = testmesh::sphere(120, 160);  // closed: only the pieces' borders are locked
#endif
  const auto nodes = buildBlockHierarchy(block, o, **simplifier);
  ASSERT_FALSE(nodes.empty());
  EXPECT_NEAR(nodes[0].simplification, double(block.triangleCount()) / 500.0, 1e-9);
  // hlod_0 has about desiredTri triangles.
  EXPECT_LE(nodes[0].info.childCount, 3u);
  EXPECT_NEAR(double(nodes[0].mesh.triangleCount()), 500.0, 0.1 * 500.0);
  // Inner nodes: near desiredTri (locked cut borders keep some more).
  std::map<std::uint32_t, std::size_t> perLevel;
  double innerSum = 0;
  int inner = 0;
  std::size_t leafSum = 0;
  for (const auto& n : nodes) {
    // A front per level: its nodes and the leaves above it (a leaf stands for its branch below).
    for (std::uint32_t l = n.info.level; l <= (n.info.childCount ? n.info.level : 16u); ++l)
      perLevel[l] += n.mesh.triangleCount();
    if (n.info.childCount) {
      innerSum += double(n.mesh.triangleCount());
      ++inner;
      EXPECT_GT(n.simplification, 1.0);
    } else {
      leafSum += n.mesh.triangleCount();
      EXPECT_LE(n.simplification, 1.0);
      EXPECT_EQ(n.info.geometricError, 0.0);
    }
  }
  ASSERT_GT(inner, 1);
  EXPECT_LT(innerSum / inner, 2.0 * 500);
  EXPECT_GT(innerSum / inner, 0.5 * 500);
  // Totals per front grow toward the leaves.
  for (auto it = std::next(perLevel.begin()); it != perLevel.end(); ++it)
    EXPECT_GE(it->second, std::prev(it)->second) << "level " << it->first;
  // The leaves hold exactly the welded block's triangles: none cut, none added, none lost.
  const Mesh welded = weldVertices(block);
  EXPECT_EQ(leafSum, welded.triangleCount());
  EXPECT_EQ(triangleSet(leavesOf(nodes)), triangleSet({&welded}));
}

// Leaves/input is 1 on a mesh whose triangles cross many planes: strips as long as the mesh, each
// of which plane cuts once split at every level (1.25-2.1x more triangles at the leaves).
TEST_P(BuildHierarchy, LongTrianglesAcrossEveryPlaneReachTheLeavesUncut) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  Mesh strips;
  const int n = 3000;
  for (int i = 0; i <= n; ++i) {
    const double y = 0.01 * i;
    strips.positions.push_back({0.0, y, 0.002 * std::sin(double(i))});
    strips.positions.push_back({30.0, y + 0.005, 0.0});
  }
  for (std::uint32_t i = 0; i < std::uint32_t(n); ++i)
    strips.indices.insert(strips.indices.end(),
                          {2 * i, 2 * i + 1, 2 * i + 3, 2 * i, 2 * i + 3, 2 * i + 2});
  BuildOptions o;
  o.desiredTri = 100;
  o.minLeafTri = 100;
  const auto nodes = buildBlockHierarchy(strips, o, **simplifier);
  std::uint32_t depth = 0;
  for (const auto& node : nodes) depth = std::max(depth, node.info.level);
  EXPECT_GE(depth, 3u);
  std::size_t leaves = 0;
  for (const Mesh* m : leavesOf(nodes)) leaves += m->triangleCount();
  EXPECT_EQ(leaves, strips.triangleCount());
  EXPECT_EQ(triangleSet(leavesOf(nodes)), triangleSet({&strips}));
}

// A piece is divided only when its children would hold minLeafTri triangles on average, no child
// holds fewer, and a piece that large stays whole only where its factor reached 1.
TEST_P(BuildHierarchy, LeavesAreNoCrumbs) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  const Mesh grid = testmesh::wavyGrid(80);  // 12,800 triangles
  for (std::uint32_t minLeaf : {200u, 1000u}) {
    BuildOptions o;
    o.desiredTri = 50;  // the factors stay above 1 to the leaves
    o.minLeafTri = minLeaf;
    const auto nodes = buildBlockHierarchy(grid, o, **simplifier);
    std::vector<std::size_t> under(nodes.size(), 0);  // original triangles under each node
    for (std::size_t i = nodes.size(); i-- > 0;) {
      if (nodes[i].info.childCount == 0) under[i] = nodes[i].mesh.triangleCount();
      if (i > 0) under[nodes[i].info.parent] += under[i];
    }
    std::size_t leaves = 0, leafTriangles = 0;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      if (nodes[i].info.childCount) {
        EXPECT_GE(under[i], 3u * minLeaf) << "node " << i;
      } else {
        ++leaves;
        leafTriangles += under[i];
        EXPECT_GE(under[i], minLeaf) << "leaf " << i;
        ASSERT_GT(i, 0u);
        const double s = nodes[nodes[i].info.parent].simplification / 3.0;
        EXPECT_TRUE(under[i] < 3u * minLeaf || s <= 1.0) << "leaf " << i;
      }
    }
    EXPECT_GT(leaves, 3u);
    EXPECT_GE(double(leafTriangles) / double(leaves), double(minLeaf)) << "minLeafTri " << minLeaf;
  }
}

TEST_P(BuildHierarchy, GeometricErrorIsMonotoneAndZeroAtLeaves) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  BuildOptions o;
  o.desiredTri = 300;
  o.minLeafTri = 300;
  const auto nodes = buildBlockHierarchy(testmesh::sphere(60, 80, 5.0), o, **simplifier);
  ASSERT_GT(nodes.size(), 4u);
  EXPECT_GT(nodes[0].info.geometricError, 0.0);
  // meshopt's error is a quadric distance estimate (loose for slabs pinned at both cut rims);
  // OpenMesh's (sqrt of a summed quadric) is a looser upper bound still.
  if (std::string(GetParam()) == "meshopt") {
    EXPECT_LT(nodes[0].info.geometricError, 10.0);  // the sphere's diameter
  }
  for (std::size_t i = 1; i < nodes.size(); ++i)
    EXPECT_GE(nodes[nodes[i].info.parent].info.geometricError, nodes[i].info.geometricError);
}

// A block whose few street triangles reach far beyond its buildings: equal widths put all but
// those few in one slab, which would leave the whole block one leaf; by count it divides.
TEST_P(BuildHierarchy, AFewTrianglesFarOutDoNotKeepTheBlockWhole) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  Mesh block = testmesh::wavyGrid(60);  // 7,200 triangles over 10 m
  const auto base = std::uint32_t(block.positions.size());
  block.positions.insert(block.positions.end(), {{10, 0, 0}, {400, 0, 0}, {400, 10, 0}});
  block.texCoords.insert(block.texCoords.end(), 3, glm::vec2(0.0f));
  block.indices.insert(block.indices.end(), {base, base + 1, base + 2});
  BuildOptions o;
  o.desiredTri = 100;
  o.minLeafTri = 1000;
  const auto nodes = buildBlockHierarchy(block, o, **simplifier);
  ASSERT_FALSE(nodes.empty());
  EXPECT_EQ(nodes[0].info.childCount, 3u);
  for (std::uint32_t c = 0; c < nodes[0].info.childCount; ++c) {
    std::size_t under = 0;
    for (const Mesh* leaf : leavesUnder(nodes, nodes[0].info.firstChild + c))
      under += leaf->triangleCount();
    EXPECT_NEAR(double(under), 7201.0 / 3.0, 60.0) << "child " << c;
  }
}

// Every front of a closed block is closed: neighbouring nodes, of one level or of two, meet on the
// same edges (no crack, no T-junction).
TEST_P(BuildHierarchy, EveryFrontOfAClosedBlockIsWatertight) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  BuildOptions o;
  o.desiredTri = 120;
  o.minLeafTri = 150;
  const Mesh block = testmesh::sphere(60, 80);
  ASSERT_EQ(openEdges({&block}), 0u);
  const auto nodes = buildBlockHierarchy(block, o, **simplifier);
  ASSERT_GT(nodes.size(), 13u);
  const auto fronts = frontsOf(nodes);
  ASSERT_GT(fronts.size(), 8u);
  for (std::size_t f = 0; f < fronts.size(); ++f)
    EXPECT_EQ(openEdges(fronts[f]), 0u) << "front " << f;
  // The check can fail: the same pieces simplified without their borders locked open cracks.
  std::vector<BlockNode> loose = nodes;
  for (std::size_t i = 0; i < loose.size(); ++i) {
    if (loose[i].info.childCount == 0) continue;
    Mesh piece;  // the original triangles of node i: its leaves
    for (const Mesh* m : leavesUnder(nodes, i)) {
      const auto base = std::uint32_t(piece.positions.size());
      piece.positions.insert(piece.positions.end(), m->positions.begin(), m->positions.end());
      for (std::uint32_t v : m->indices) piece.indices.push_back(base + v);
    }
    loose[i].mesh =
        (*simplifier)->simplify(weldVertices(piece), nodes[i].mesh.triangleCount()).mesh;
  }
  std::size_t open = 0;
  for (const auto& front : frontsOf(loose)) open += openEdges(front);
  EXPECT_GT(open, 0u);
}

// Blocks cut from one mesh meet as nodes of one block do: any level of one beside any of another.
TEST(BuildBlocks, BlocksCutFromOneMeshMeetWatertightAtAnyTwoLevels) {
  auto simplifier = makeSimplifier("meshopt");
  ASSERT_TRUE(simplifier);
  Model model;
  model.meshes.push_back(testmesh::sphere(60, 80));
  const auto blocks = cutIntoBlocks(model, 2500);
  ASSERT_GE(blocks.size(), 4u);
  std::size_t inBlocks = 0;
  for (const auto& b : blocks) {
    EXPECT_LE(b.mesh.triangleCount(), 2500u);
    EXPECT_FALSE(b.seam.empty());
    inBlocks += b.mesh.triangleCount();
  }
  EXPECT_EQ(inBlocks, model.meshes[0].triangleCount());
  BuildOptions o;
  o.desiredTri = 100;
  o.minLeafTri = 100;
  const auto levelFront = [](const std::vector<BlockNode>& nodes, std::uint32_t level) {
    std::vector<const Mesh*> front;
    for (const auto& n : nodes)
      if (n.info.level == level || (n.info.childCount == 0 && n.info.level < level))
        front.push_back(&n.mesh);
    return front;
  };
  // Each block at level 0, except block k at its leaves; then the other way round.
  const auto check = [&](bool withSeams) {
    std::vector<std::vector<BlockNode>> built;
    for (const auto& b : blocks)
      built.push_back(buildBlockHierarchy(
          b.mesh, o, **simplifier,
          withSeams ? std::span<const glm::dvec3>(b.seam) : std::span<const glm::dvec3>()));
    std::size_t open = 0;
    for (std::size_t k = 0; k < built.size(); ++k)
      for (std::uint32_t coarse : {0u, 16u}) {
        std::vector<const Mesh*> front;
        for (std::size_t j = 0; j < built.size(); ++j) {
          const auto part = levelFront(built[j], j == k ? 16u - coarse : coarse);
          front.insert(front.end(), part.begin(), part.end());
        }
        open += openEdges(front);
      }
    return open;
  };
  EXPECT_EQ(check(true), 0u);
  // Without the seam the blocks' own borders move while simplifying: the check can fail.
  EXPECT_GT(check(false), 0u);
}

TEST(BuildBlocks, APileOfCoincidentTrianglesIsNotMultipliedByTheCuts) {
  // 2,000 copies of one quad: every cut cuts all of them, at every level. 20,000 copies once grew
  // 211-fold on the way to the leaves (bad_alloc at 200,000 copies).
  Mesh pile;
  pile.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (int i = 0; i < 2000; ++i) pile.indices.insert(pile.indices.end(), {0, 1, 2, 0, 2, 3});
  const std::size_t input = pile.triangleCount();
  Model model;
  model.meshes.push_back(pile);
  const auto blocks = cutIntoBlocks(model, 1000);
  std::size_t inBlocks = 0;
  for (const auto& b : blocks) inBlocks += b.mesh.triangleCount();
  EXPECT_EQ(inBlocks, input);
  auto simplifier = makeSimplifier("openmesh");
  ASSERT_TRUE(simplifier);
  BuildOptions o;
  o.desiredTri = 100;
  for (const auto& b : blocks) {
    const auto nodes = buildBlockHierarchy(b.mesh, o, **simplifier, b.seam);
    std::size_t leaves = 0;
    for (const auto& n : nodes)
      if (n.info.childCount == 0) leaves += n.mesh.triangleCount();
    EXPECT_EQ(leaves, b.mesh.triangleCount());  // the leaves hold every triangle, once
  }
}

// A block's sides (where its ground meets its neighbours'): at every level the block still
// covers its whole footprint, corners included, though the straight runs between the corners may
// lose vertices. Before the sides were kept, coarse levels of the city cut the corners where
// streets cross and the sky showed through between the blocks.
TEST_P(BuildHierarchy, BlockSidesKeepTheFootprintAtEveryLevel) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  // Ground with a bumpy middle and a flat, straight border: 10 x 10, z = 0 on the border.
  Mesh ground = testmesh::wavyGrid(60);
  for (auto& p : ground.positions)
    p.z = 0.4 * std::sin(M_PI * p.x / 10.0) * std::sin(M_PI * p.y / 10.0) * std::sin(p.x + p.y);
  const std::vector<CutPlane> sides = {{0, 0.0}, {0, 10.0}, {1, 0.0}, {1, 10.0}};
  BuildOptions o;
  o.desiredTri = 20;
  o.minLeafTri = 100;
  const auto nodes = buildBlockHierarchy(ground, o, **simplifier, {}, sides);
  ASSERT_GT(nodes.size(), 4u);
  // Per level (its nodes and the leaves above it), the footprint's edge seen from above is
  // covered: points 0.01, 0.05 and 0.2 inside the sides, corners included.
  std::vector<glm::dvec2> points;
  for (double in : {0.01, 0.05, 0.2})
    for (int i = 0; i <= 200; ++i) {
      const double t = in + (10.0 - 2.0 * in) * i / 200.0;
      points.insert(points.end(), {{t, in}, {t, 10.0 - in}, {in, t}, {10.0 - in, t}});
    }
  std::map<std::uint32_t, std::size_t> triangles;
  std::map<std::uint32_t, std::vector<glm::dvec3>> levelTriangles;  // three corners each
  for (const BlockNode& n : nodes) {
    triangles[n.info.level] += n.mesh.triangleCount();
    // A leaf stands for its branch at every deeper level too.
    for (std::uint32_t l = n.info.level; l <= (n.info.childCount ? n.info.level : 16u); ++l)
      for (std::uint32_t v : n.mesh.indices) levelTriangles[l].push_back(n.mesh.positions[v]);
  }
  const std::uint32_t depth = triangles.rbegin()->first;
  for (const auto& [level, corners] : levelTriangles) {
    if (level > depth) break;
    std::size_t uncovered = 0;
    for (const glm::dvec2& q : points) {
      bool inside = false;
      for (std::size_t t = 0; t + 2 < corners.size() && !inside; t += 3) {
        const glm::dvec2 a(corners[t]), b(corners[t + 1]), c(corners[t + 2]);
        const double d1 = (b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x);
        const double d2 = (c.x - b.x) * (q.y - b.y) - (c.y - b.y) * (q.x - b.x);
        const double d3 = (a.x - c.x) * (q.y - c.y) - (a.y - c.y) * (q.x - c.x);
        inside = (d1 >= 0 && d2 >= 0 && d3 >= 0) || (d1 <= 0 && d2 <= 0 && d3 <= 0);
      }
      uncovered += !inside;
    }
    EXPECT_EQ(uncovered, 0u) << "level " << level << " of " << depth;
  }
  // And the root did simplify: the straight runs did not freeze it.
  EXPECT_LT(triangles[0], ground.triangleCount() / 20);
}

INSTANTIATE_TEST_SUITE_P(BothSimplifiers, BuildHierarchy, testing::Values("meshopt", "openmesh"));

class BuildSimplifier : public testing::TestWithParam<const char*> {};

TEST_P(BuildSimplifier, KeepsLockedVerticesAndMayRemoveOtherBorderVertices) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  const Mesh grid = weldVertices(testmesh::wavyGrid(40));
  // Lock the x == 0 and y == 10 borders only (two cuts).
  std::vector<std::uint8_t> locked(grid.positions.size(), 0);
  for (std::size_t v = 0; v < grid.positions.size(); ++v)
    locked[v] = grid.positions[v].x == 0.0 || grid.positions[v].y == 10.0;
  const SimplifiedMesh s = (*simplifier)->simplify(grid, 50, locked);
  EXPECT_LT(s.mesh.triangleCount(), grid.triangleCount() / 4);
  std::set<PosKey> kept;
  for (const auto& p : s.mesh.positions) kept.insert({p});
  int lockedCount = 0, otherBorder = 0, otherBorderKept = 0;
  for (std::size_t v = 0; v < grid.positions.size(); ++v) {
    const auto& p = grid.positions[v];
    if (locked[v]) {
      ++lockedCount;
      EXPECT_TRUE(kept.count({p})) << p.x << "," << p.y;
    } else if (p.y == 0.0 || p.x == 10.0) {
      ++otherBorder;
      otherBorderKept += kept.count({p});
    }
  }
  EXPECT_EQ(lockedCount, 81);
  EXPECT_EQ(otherBorder, 79);
  EXPECT_LT(otherBorderKept, otherBorder / 2);  // unlocked borders simplify
}

TEST_P(BuildSimplifier, RemovesClosedBoxesWhoseFacesHaveTheirOwnTextureCoordinates) {
  // Boxes with one texture rectangle per face: every corner has three (position, uv) vertices.
  // Welded on position and uv they could not lose a single vertex; on position alone they can.
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  Mesh boxes;
  for (int i = 0; i < 200; ++i) {
    const Mesh b = testmesh::box(glm::dvec3(i * 3.0, 0, 0), glm::dvec3(i * 3.0 + 1, 1, 1 + i % 3));
    const auto base = std::uint32_t(boxes.positions.size());
    boxes.positions.insert(boxes.positions.end(), b.positions.begin(), b.positions.end());
    boxes.normals.insert(boxes.normals.end(), b.normals.begin(), b.normals.end());
    boxes.texCoords.insert(boxes.texCoords.end(), b.texCoords.begin(), b.texCoords.end());
    for (auto idx : b.indices) boxes.indices.push_back(base + idx);
  }
  const Mesh welded = weldVertices(boxes);
  ASSERT_EQ(welded.positions.size(), 200u * 24u);
  const SimplifiedMesh s = (*simplifier)->simplify(welded, 600);
  // OpenMesh's decimater folds boxes; the shape guard keeps some of them whole.
  EXPECT_LE(s.mesh.triangleCount(), GetParam() == std::string("openmesh") ? 1000u : 800u);
  // Kept triangles take a vertex whose normal matches them: for an unsimplified box face, its own.
  ASSERT_EQ(s.mesh.normals.size(), s.mesh.positions.size());
}

TEST_P(BuildSimplifier, BoxesTouchingASurfaceAtOneCornerDoNotPinIt) {
  // Each small box shares one corner position with a grid vertex: a non-manifold vertex, which
  // an edge collapser must freeze unless the simplifier splits it into its two fans.
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  Mesh m = weldVertices(testmesh::wavyGrid(30));
  const std::size_t gridVertices = m.positions.size();
  for (std::size_t v = 0; v < gridVertices; v += 3) {
    const glm::dvec3 lo = m.positions[v];
    const Mesh b = testmesh::box(lo, lo + glm::dvec3(0.05, 0.05, 0.4));
    const auto base = std::uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), b.positions.begin(), b.positions.end());
    m.normals.resize(base, glm::vec3(0, 0, 1));
    m.normals.insert(m.normals.end(), b.normals.begin(), b.normals.end());
    m.texCoords.insert(m.texCoords.end(), b.texCoords.begin(), b.texCoords.end());
    for (auto idx : b.indices) m.indices.push_back(base + idx);
  }
  m = weldVertices(m);
  ASSERT_GT(m.triangleCount(), 5000u);
  const SimplifiedMesh s = (*simplifier)->simplify(m, 400);
  // OpenMesh turns many boxes over; the shape guard locks them back, at about 4x the target
  // (not yet fixed: OpenMesh needs a collapse check against the original surface).
  EXPECT_LE(s.mesh.triangleCount(), GetParam() == std::string("openmesh") ? 1600u : 500u);
  EXPECT_GT(s.mesh.triangleCount(), 100u);
}

TEST_P(BuildSimplifier, KeepsTextureCoordinatesOfTheVerticesItKeeps) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  const Mesh grid = weldVertices(testmesh::wavyGrid(30));
  const SimplifiedMesh s = (*simplifier)->simplify(grid, 200);
  ASSERT_EQ(s.mesh.texCoords.size(), s.mesh.positions.size());
  std::map<PosKey, glm::vec2> uvOf;
  for (std::size_t i = 0; i < grid.positions.size(); ++i)
    uvOf[{grid.positions[i]}] = grid.texCoords[i];
  for (std::size_t i = 0; i < s.mesh.positions.size(); ++i) {
    auto it = uvOf.find({s.mesh.positions[i]});
    ASSERT_NE(it, uvOf.end());
    EXPECT_EQ(it->second, s.mesh.texCoords[i]);
  }
}

INSTANTIATE_TEST_SUITE_P(BothSimplifiers, BuildSimplifier, testing::Values("meshopt", "openmesh"));

TEST(BuildSimplifierFactory, RejectsUnknownNames) {
  auto s = makeSimplifier("qslim");
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("meshopt"), std::string::npos);
}

TEST(BuildBlocks, MeshIsCutIntoBoundedBlocksGroupedByMaterial) {
  Model model;
  model.meshes.push_back(testmesh::wavyGrid(50));  // 5000 triangles
  Mesh other = testmesh::wavyGrid(10, 10.0, glm::dvec3(0, 0, 5));
  other.texture = testmesh::checkerTexture(16, 16);
  model.meshes.push_back(other);
  const auto blocks = cutIntoBlocks(model, 1000);
  std::size_t total = 0;
  double area = 0;
  int textured = 0;
  for (const auto& [b, seam, sides] : blocks) {
    EXPECT_LE(b.triangleCount(), 1000u);
    total += b.triangleCount();
    area += surfaceArea(b);
    if (b.texture) {
      ++textured;
      EXPECT_EQ(b.triangleCount(), 200u);  // the textured mesh stays on its own
      EXPECT_TRUE(seam.empty());
    } else {
      EXPECT_FALSE(seam.empty());  // cut from the 5000-triangle grid
    }
  }
  EXPECT_EQ(textured, 1);
  EXPECT_EQ(total, model.triangleCount());
  const double expected = surfaceArea(model.meshes[0]) + surfaceArea(model.meshes[1]);
  EXPECT_NEAR(area, expected, 1e-9 * expected);
}

TEST(BuildTexture, CropsToTheUsedRectangleAndKeepsAtLeastEightPixels) {
  const auto tex = testmesh::checkerTexture(64, 64);
  std::vector<glm::vec2> uv = {{0.25f, 0.25f}, {0.5f, 0.25f}, {0.5f, 0.5f}};
  auto out = prepareNodeTexture(*tex, uv, 1.0);
  ASSERT_TRUE(out);
  EXPECT_EQ(out->width, 16 + 2);  // 16 texels and a margin of one each side
  EXPECT_NEAR(uv[0].x, 1.0f / 18.0f, 1e-6);
  EXPECT_NEAR(uv[1].x, 17.0f / 18.0f, 1e-6);
  std::vector<glm::vec2> all = {{0, 0}, {1, 0}, {1, 1}};
  auto small = prepareNodeTexture(*tex, all, 1e6);
  ASSERT_TRUE(small);
  EXPECT_EQ(small->width, 8);
  EXPECT_EQ(small->height, 8);
  auto half = prepareNodeTexture(*tex, all, 4.0);
  EXPECT_EQ(half->width, 32);
}

TEST(BuildTexture, BoxFilterAveragesPixels) {
  Image img;
  img.width = 2;
  img.height = 2;
  img.pixels = {0, 0, 0, 255, 100, 0, 0, 255, 0, 200, 0, 255, 100, 200, 40, 255};
  const Image out = resizeImage(img, 1, 1);
  EXPECT_EQ(out.pixels, (std::vector<std::uint8_t>{50, 100, 10, 255}));
}
