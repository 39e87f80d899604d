// The HLOD builder (Lakhia III-A/B) on hand-built meshes: equations 1-3, plane splits, the
// hierarchy's shape, seams and the simplifiers' contract.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <set>

#include "BuildTestMeshes.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/builder/PlaneSplit.h"
#include "hlod/builder/Preprocess.h"
#include "hlod/builder/SeamVertices.h"
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

std::set<PosKey> verticesOnPlane(const Mesh& m, int axis, double value) {
  std::set<PosKey> out;
  for (std::uint32_t i : m.indices)
    if (m.positions[i][axis] == value) out.insert({m.positions[i]});
  return out;
}

// Counts T-junctions: a vertex of any node lying strictly inside a seam edge (an edge on one of
// the node's cutting planes) of another node. Slivers thinner than 1e-9 of their longest edge, and
// triangles a few ulps across, are skipped: cuts through the line where two planes meet leave
// some (edges of 1e-16 m), and no rasteriser finds a gap beside them.
int countTJunctions(const std::vector<const BlockNode*>& nodes) {
  std::map<CutPlane, std::set<PosKey>> onPlane;
  for (const BlockNode* n : nodes)
    for (const CutPlane& plane : n->planes)
      for (std::uint32_t i : n->mesh.indices)
        if (plane.contains(n->mesh.positions[i])) onPlane[plane].insert({n->mesh.positions[i]});
  int found = 0;
  for (const BlockNode* n : nodes) {
    const Mesh& m = n->mesh;
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
      const glm::dvec3 p[3] = {m.positions[m.indices[t]], m.positions[m.indices[t + 1]],
                               m.positions[m.indices[t + 2]]};
      double longest = 0;
      for (int e = 0; e < 3; ++e) longest = std::max(longest, glm::length(p[(e + 1) % 3] - p[e]));
      const double area2 = glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
      const double scale = 1.0 + glm::length(p[0]);
      if (area2 <= 1e-9 * longest * longest || longest < 1e-12 * scale) continue;
      for (int e = 0; e < 3; ++e) {
        const glm::dvec3 a = p[e], b = p[(e + 1) % 3];
        for (const CutPlane& plane : n->planes) {
          if (!plane.contains(a) || !plane.contains(b)) continue;
          const double len2 = glm::dot(b - a, b - a);
          for (const PosKey& k : onPlane[plane]) {
            const double t01 = glm::dot(k.p - a, b - a) / len2;
            if (!(t01 > 1e-9 && t01 < 1 - 1e-9)) continue;
            const glm::dvec3 q = a + t01 * (b - a);
            if (glm::length(k.p - q) < 1e-9 * std::sqrt(len2)) ++found;
          }
        }
      }
    }
  }
  return found;
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

TEST(BuildPlaneSplit, CrossingTriangleBecomesThreeWithTwoNewVerticesOnThePlane) {
  Mesh m = triangles({{-1, 0, 0}, {1, 0, 0}, {1, 1, 0}});
  m.texCoords = {{0, 0}, {1, 0}, {1, 1}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  const PlaneSplitResult r = splitByPlane(m, 0, 0.0);
  EXPECT_EQ(r.below.triangleCount() + r.above.triangleCount(), 3u);
  EXPECT_EQ(r.below.triangleCount(), 1u);
  EXPECT_DOUBLE_EQ(surfaceArea(r.below) + surfaceArea(r.above), surfaceArea(m));
  for (const auto& p : r.below.positions) EXPECT_LE(p.x, 0.0);
  for (const auto& p : r.above.positions) EXPECT_GE(p.x, 0.0);
  EXPECT_EQ(verticesOnPlane(r.below, 0, 0.0), verticesOnPlane(r.above, 0, 0.0));
  EXPECT_EQ(verticesOnPlane(r.below, 0, 0.0).size(), 2u);
  // The uv of the vertex where edge (-1,0)-(1,0) meets x=0 is interpolated halfway.
  bool found = false;
  for (std::size_t i = 0; i < r.above.positions.size(); ++i)
    if (r.above.positions[i] == glm::dvec3(0, 0, 0)) {
      found = true;
      EXPECT_FLOAT_EQ(r.above.texCoords[i].x, 0.5f);
      EXPECT_EQ(r.above.normals[i], glm::vec3(0, 0, 1));
    }
  EXPECT_TRUE(found);
}

TEST(BuildPlaneSplit, VertexOnThePlaneIsNotSplit) {
  // Vertex 0 on the plane, the others on opposite sides: one new vertex, two triangles.
  const Mesh m = triangles({{0, 1, 0}, {-1, 0, 0}, {1, 0, 0}});
  const PlaneSplitResult r = splitByPlane(m, 0, 0.0);
  EXPECT_EQ(r.below.triangleCount(), 1u);
  EXPECT_EQ(r.above.triangleCount(), 1u);
  EXPECT_DOUBLE_EQ(surfaceArea(r.below) + surfaceArea(r.above), surfaceArea(m));
  // Two vertices on the plane, the third on one side: no split at all.
  const PlaneSplitResult r2 = splitByPlane(triangles({{0, 1, 0}, {0, -1, 0}, {1, 0, 0}}), 0, 0.0);
  EXPECT_EQ(r2.below.triangleCount(), 0u);
  EXPECT_EQ(r2.above.triangleCount(), 1u);
  EXPECT_EQ(r2.above.positions.size(), 3u);
}

TEST(BuildPlaneSplit, ConservesAreaOfRandomTrianglesWithoutNaNs) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mesh m;
  for (int t = 0; t < 3000; ++t) {
    for (int k = 0; k < 3; ++k) {
      glm::dvec3 p(u(rng), u(rng), u(rng));
      // Some vertices exactly on the plane or a hair off it (nearly parallel edges, slivers).
      if (t % 5 == 0 && k == 0) p.x = 0.1;
      if (t % 7 == 0 && k == 1) p.x = 0.1 + 1e-15;
      if (t % 11 == 0) p.x = 0.1 + (k - 1) * 1e-13;
      m.positions.push_back(p);
      m.normals.push_back(glm::normalize(glm::vec3(p)));
      m.texCoords.emplace_back(float(u(rng)), float(u(rng)));
      m.indices.push_back(std::uint32_t(m.positions.size() - 1));
    }
  }
  const double before = surfaceArea(m);
  const PlaneSplitResult r = splitByPlane(m, 0, 0.1);
  const double after = surfaceArea(r.below) + surfaceArea(r.above);
  EXPECT_NEAR(after, before, 1e-9 * before);
  EXPECT_GE(r.below.triangleCount() + r.above.triangleCount(), m.triangleCount());
  for (const Mesh* h : {&r.below, &r.above}) {
    for (const auto& p : h->positions) EXPECT_TRUE(finite(p));
    for (const auto& n : h->normals) EXPECT_TRUE(std::isfinite(n.x + n.y + n.z));
    for (const auto& t : h->texCoords) EXPECT_TRUE(std::isfinite(t.x + t.y));
  }
  for (const auto& p : r.below.positions) EXPECT_LE(p.x, 0.1);
  for (const auto& p : r.above.positions) EXPECT_GE(p.x, 0.1);
}

TEST(BuildPlaneSplit, SharedEdgeGivesOneBitIdenticalVertexOnBothSides) {
  const Mesh grid = testmesh::wavyGrid(20);
  const double plane = 3.3333333333333;
  const PlaneSplitResult r = splitByPlane(grid, 0, plane);
  EXPECT_EQ(verticesOnPlane(r.below, 0, plane), verticesOnPlane(r.above, 0, plane));
  EXPECT_NEAR(surfaceArea(r.below) + surfaceArea(r.above), surfaceArea(grid),
              1e-9 * surfaceArea(grid));
  // Welding each half finds no duplicate cut vertices (each edge cut once).
  EXPECT_EQ(weldVertices(r.below).positions.size(), r.below.positions.size());
}

class BuildHierarchy : public testing::TestWithParam<const char*> {};

TEST_P(BuildHierarchy, ChildrenPartitionTheirParentsRegion) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  BuildOptions o;
  o.desiredTri = 200;
  const auto nodes = buildBlockHierarchy(testmesh::wavyGrid(60), o, **simplifier);
  ASSERT_GT(nodes.size(), 4u);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const BlockNode& n = nodes[i];
    if (n.info.childCount == 0) continue;
    ASSERT_EQ(n.cutPlanes.size(), 2u);
    const int a = n.cutAxis;
    // Each child's box lies in the parent's box and within its slab along the cut axis.
    std::vector<double> walls = {n.info.bounds.min[a], n.cutPlanes[0], n.cutPlanes[1],
                                 n.info.bounds.max[a]};
    for (std::uint32_t c = 0; c < n.info.childCount; ++c) {
      const BlockNode& child = nodes[n.info.firstChild + c];
      EXPECT_EQ(child.info.parent, i);
      EXPECT_EQ(child.info.level, n.info.level + 1);
      for (int k = 0; k < 3; ++k) {
        EXPECT_GE(child.info.bounds.min[k], n.info.bounds.min[k]);
        EXPECT_LE(child.info.bounds.max[k], n.info.bounds.max[k]);
      }
      // Find the child's slab: the one its box centre lies in.
      const double mid = child.info.bounds.centre()[a];
      int slab = 0;
      while (slab < 2 && mid > walls[slab + 1]) ++slab;
      EXPECT_GE(child.info.bounds.min[a], walls[slab]);
      EXPECT_LE(child.info.bounds.max[a], walls[slab + 1]);
    }
  }
}

TEST_P(BuildHierarchy, TriangleCountsFollowTheSimplificationFactors) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  BuildOptions o;
  o.desiredTri = 500;
#ifdef HLODR_SANITIZE_BUILD
  const Mesh block = testmesh::sphere(80, 100);  // 16k triangles: the sanitizers are 4-15x slower
#else
  const Mesh block = testmesh::sphere(120, 160);  // closed: only the cuts are locked
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
    perLevel[n.info.level] += n.mesh.triangleCount();
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
  // Totals per level grow toward the leaves.
  for (auto it = std::next(perLevel.begin()); it != perLevel.end(); ++it)
    EXPECT_GE(it->second, std::prev(it)->second);
  // The leaves hold exactly the original triangles plus those the cuts created: replaying the
  // recorded cuts on the original block gives the same count and area.
  std::vector<Mesh> replay = {weldVertices(block)};
  std::size_t replayLeaves = 0;
  double replayArea = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].info.childCount == 0) {
      replayLeaves += replay[i].triangleCount();
      replayArea += surfaceArea(replay[i]);
      continue;
    }
    Mesh rest = replay[i];
    std::vector<Mesh> slabs;
    for (double plane : nodes[i].cutPlanes) {
      auto r = splitByPlane(rest, nodes[i].cutAxis, plane);
      slabs.push_back(std::move(r.below));
      rest = std::move(r.above);
    }
    slabs.push_back(std::move(rest));
    for (auto& s : slabs)
      if (s.triangleCount()) replay.push_back(std::move(s));
  }
  // Seam vertices inserted against T-junctions add a few triangles and no area.
  EXPECT_GE(leafSum, replayLeaves);
  EXPECT_LE(double(leafSum), 1.02 * double(replayLeaves));
  EXPECT_GE(leafSum, block.triangleCount());
  EXPECT_NEAR(replayArea, surfaceArea(block), 1e-9 * surfaceArea(block));
  double leafArea = 0;
  for (const auto& n : nodes)
    if (n.info.childCount == 0) leafArea += surfaceArea(n.mesh);
  EXPECT_NEAR(leafArea, surfaceArea(block), 1e-9 * surfaceArea(block));
}

TEST_P(BuildHierarchy, GeometricErrorIsMonotoneAndZeroAtLeaves) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  BuildOptions o;
  o.desiredTri = 300;
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

TEST_P(BuildHierarchy, SeamsMatchAtTheSameLevelAndAcrossLevels) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  BuildOptions o;
  o.desiredTri = 150;
  const auto nodes = buildBlockHierarchy(testmesh::wavyGrid(80), o, **simplifier);
  ASSERT_GT(nodes.size(), 13u);
  int checkedSame = 0, checkedAcross = 0;
  for (const auto& parent : nodes) {
    for (std::uint32_t c = 0; c + 1 < parent.info.childCount; ++c) {
      const BlockNode& left = nodes[parent.info.firstChild + c];
      const BlockNode& right = nodes[parent.info.firstChild + c + 1];
      const int a = parent.cutAxis;
      const double plane = parent.cutPlanes[c];
      if (right.info.bounds.min[a] != plane && left.info.bounds.max[a] != plane) continue;
      // Same level: the vertices on the shared plane are the same, bit for bit, both ways.
      const auto l = verticesOnPlane(left.mesh, a, plane),
                 r = verticesOnPlane(right.mesh, a, plane);
      EXPECT_EQ(l, r);
      ++checkedSame;
      // Across levels: the coarser node's seam vertices all appear in the finer neighbours
      // (its children), which may add more on the seam's segments.
      if (right.info.childCount) {
        std::set<PosKey> fine;
        for (std::uint32_t k = 0; k < right.info.childCount; ++k) {
          const auto v = verticesOnPlane(nodes[right.info.firstChild + k].mesh, a, plane);
          fine.insert(v.begin(), v.end());
        }
        // No T-junction: the coarse side has every vertex the fine side has on the seam.
        EXPECT_EQ(l, fine);
        ++checkedAcross;
      }
    }
  }
  EXPECT_GT(checkedSame, 3);
  EXPECT_GT(checkedAcross, 1);
}

TEST_P(BuildHierarchy, NoTJunctionsBetweenAnyNodesOfABlock) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  BuildOptions o;
  o.desiredTri = 120;
  const auto nodes = buildBlockHierarchy(testmesh::wavyGrid(70), o, **simplifier);
  ASSERT_GT(nodes.size(), 13u);
  std::vector<const BlockNode*> all;
  for (const auto& n : nodes) all.push_back(&n);
  EXPECT_EQ(countTJunctions(all), 0);
  // Without the insertion the same cuts leave T-junctions: the check can fail.
  std::vector<BlockNode> raw;
  std::vector<Mesh> pieces = {weldVertices(testmesh::wavyGrid(70))};
  std::vector<std::vector<CutPlane>> planes = {{}};
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    BlockNode n;
    n.mesh = pieces[i];
    n.planes = planes[i];
    raw.push_back(n);
    if (!nodes[i].info.childCount) continue;
    Mesh rest = pieces[i];
    for (std::size_t k = 0; k <= nodes[i].cutPlanes.size(); ++k) {
      std::vector<CutPlane> own = planes[i];
      if (k > 0) own.push_back({nodes[i].cutAxis, nodes[i].cutPlanes[k - 1]});
      if (k < nodes[i].cutPlanes.size()) {
        own.push_back({nodes[i].cutAxis, nodes[i].cutPlanes[k]});
        auto r = splitByPlane(rest, nodes[i].cutAxis, nodes[i].cutPlanes[k]);
        pieces.push_back(std::move(r.below));
        rest = std::move(r.above);
      } else {
        pieces.push_back(rest);
      }
      planes.push_back(own);
    }
  }
  std::vector<const BlockNode*> rawAll;
  for (const auto& n : raw) rawAll.push_back(&n);
  EXPECT_GT(countTJunctions(rawAll), 0);
}

TEST(BuildBlocks, NoTJunctionsAcrossBlocksCutFromOneMesh) {
  auto simplifier = makeSimplifier("meshopt");
  ASSERT_TRUE(simplifier);
  // A grid with a gap cut out, so that blocks differ in size and their own cuts meet the shared
  // planes at different places.
  Mesh grid = testmesh::wavyGrid(90);
  std::vector<std::uint32_t> kept;
  for (std::size_t t = 0; t + 2 < grid.indices.size(); t += 3) {
    const glm::dvec3 c = (grid.positions[grid.indices[t]] + grid.positions[grid.indices[t + 1]] +
                          grid.positions[grid.indices[t + 2]]) /
                         3.0;
    if (c.x > 5.0 && c.y > 3.05 && c.y < 5.0) continue;
    kept.insert(kept.end(), grid.indices.begin() + t, grid.indices.begin() + t + 3);
  }
  grid.indices = kept;
  Model model;
  model.meshes.push_back(grid);
  const auto blocks = cutIntoBlocks(model, 4500);
  ASSERT_GE(blocks.size(), 4u);
  BuildOptions o;
  o.desiredTri = 200;
  SeamVertices seams;
  for (const auto& b : blocks) seams.merge(planBlockSeams(b.mesh, o, b.planes));
  std::vector<std::vector<BlockNode>> built;
  for (const auto& b : blocks)
    built.push_back(buildBlockHierarchy(b.mesh, o, **simplifier, b.planes, &seams));
  std::vector<const BlockNode*> all;
  for (const auto& nodes : built)
    for (const auto& n : nodes) all.push_back(&n);
  EXPECT_EQ(countTJunctions(all), 0);
  // Without the neighbours' seam vertices the blocks' own cuts leave T-junctions between blocks.
  std::vector<std::vector<BlockNode>> alone;
  for (const auto& b : blocks)
    alone.push_back(buildBlockHierarchy(b.mesh, o, **simplifier, b.planes));
  std::vector<const BlockNode*> allAlone;
  for (const auto& nodes : alone)
    for (const auto& n : nodes) allAlone.push_back(&n);
  EXPECT_GT(countTJunctions(allAlone), 0);
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
  EXPECT_LE(inBlocks, 2 * input);
  auto simplifier = makeSimplifier("openmesh");
  ASSERT_TRUE(simplifier);
  BuildOptions o;
  o.desiredTri = 100;
  for (const auto& b : blocks) {
    const auto nodes = buildBlockHierarchy(b.mesh, o, **simplifier, b.planes);
    std::size_t leaves = 0;
    for (const auto& n : nodes)
      if (n.info.childCount == 0) leaves += n.mesh.triangleCount();
    EXPECT_GE(leaves, b.mesh.triangleCount());  // the leaves still hold every triangle
    EXPECT_LE(leaves, 2 * b.mesh.triangleCount());
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
  const auto nodes = buildBlockHierarchy(ground, o, **simplifier, {}, nullptr, sides);
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
  for (const auto& [b, planes, sides] : blocks) {
    EXPECT_LE(b.triangleCount(), 1000u);
    total += b.triangleCount();
    area += surfaceArea(b);
    if (b.texture) {
      ++textured;
      EXPECT_EQ(b.triangleCount(), 200u);  // the textured mesh stays on its own
      EXPECT_TRUE(planes.empty());
    } else {
      EXPECT_FALSE(planes.empty());  // cut from the 5000-triangle grid
    }
  }
  EXPECT_EQ(textured, 1);
  EXPECT_GE(total, model.triangleCount());
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
