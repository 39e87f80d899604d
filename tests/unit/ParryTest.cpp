// Parry et al. sec. 3-5: faces and facades, the sphere hierarchy, silhouettes and the
// simplification arrays, on hand-built meshes.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>

#include "BuildTestMeshes.h"
#include "hlod/builder/Simplifier.h"
#include "hlod/metrics/SimplifiedFacing.h"
#include "hlod/parry/Faces.h"
#include "hlod/parry/ParryPiece.h"
#include "hlod/parry/SimplificationArrays.h"
#include "hlod/parry/SphereHierarchy.h"

namespace hlod {
namespace {

// A flat grid of nx x ny cells over [0, w] x [0, h] at z = 0, facing +z.
Mesh flatGrid(int nx, int ny, double w, double h) {
  Mesh m;
  for (int y = 0; y <= ny; ++y)
    for (int x = 0; x <= nx; ++x) m.positions.emplace_back(w * x / nx, h * y / ny, 0.0);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const auto a = std::uint32_t(y * (nx + 1) + x), b = a + 1, c = a + std::uint32_t(nx + 1),
                 d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
  return m;
}

// Adds the quad a b c d (counter-clockwise seen from outside) with its own four vertices.
void addQuad(Mesh& m, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 d) {
  const auto base = std::uint32_t(m.positions.size());
  m.positions.insert(m.positions.end(), {a, b, c, d});
  m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

// The box [0,10]^3 with a window recessed 1 m into its -y side: the wall is a ring of four quads
// around the opening x in [4,6], z in [4,6]; the recess has four sides and a back at y = 1.
// Welded by position, so the wall and the recess share the opening's vertices.
Mesh boxWithRecessedWindow() {
  Mesh m;
  using V = glm::dvec3;
  addQuad(m, V(0, 0, 0), V(0, 10, 0), V(10, 10, 0), V(10, 0, 0));      // bottom (-z)
  addQuad(m, V(10, 0, 10), V(10, 10, 10), V(0, 10, 10), V(0, 0, 10));  // top (+z)
  addQuad(m, V(0, 0, 0), V(0, 0, 10), V(0, 10, 10), V(0, 10, 0));      // -x
  addQuad(m, V(10, 10, 0), V(10, 10, 10), V(10, 0, 10), V(10, 0, 0));  // +x
  addQuad(m, V(0, 10, 0), V(0, 10, 10), V(10, 10, 10), V(10, 10, 0));  // +y
  // The -y wall around the opening (normal -y: counter-clockwise seen from -y).
  addQuad(m, V(0, 0, 0), V(10, 0, 0), V(6, 0, 4), V(4, 0, 4));
  addQuad(m, V(10, 0, 0), V(10, 0, 10), V(6, 0, 6), V(6, 0, 4));
  addQuad(m, V(10, 0, 10), V(0, 0, 10), V(4, 0, 6), V(6, 0, 6));
  addQuad(m, V(0, 0, 10), V(0, 0, 0), V(4, 0, 4), V(4, 0, 6));
  // The recess: back (-y), sill (+z), lintel (-z), left side (+x), right side (-x).
  addQuad(m, V(4, 1, 4), V(6, 1, 4), V(6, 1, 6), V(4, 1, 6));
  addQuad(m, V(4, 0, 4), V(6, 0, 4), V(6, 1, 4), V(4, 1, 4));
  addQuad(m, V(6, 0, 6), V(4, 0, 6), V(4, 1, 6), V(6, 1, 6));
  addQuad(m, V(4, 0, 6), V(4, 0, 4), V(4, 1, 4), V(4, 1, 6));
  addQuad(m, V(6, 0, 4), V(6, 0, 6), V(6, 1, 6), V(6, 1, 4));
  return weldVertices(m);
}

using Tri = std::array<glm::dvec3, 3>;

// A triangle as its corners from the lowest (lexicographic), keeping the winding.
Tri canonical(Tri t) {
  const auto less = [](const glm::dvec3& a, const glm::dvec3& b) {
    return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
  };
  while (less(t[1], t[0]) || less(t[2], t[0])) std::rotate(t.begin(), t.begin() + 1, t.end());
  return t;
}

std::multiset<std::array<double, 9>> triangleSet(const std::vector<glm::dvec3>& at,
                                                 std::span<const std::uint32_t> indices) {
  std::multiset<std::array<double, 9>> out;
  for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
    const Tri t = canonical({at[indices[i]], at[indices[i + 1]], at[indices[i + 2]]});
    out.insert({t[0].x, t[0].y, t[0].z, t[1].x, t[1].y, t[1].z, t[2].x, t[2].y, t[2].z});
  }
  return out;
}

std::vector<glm::dvec3> centres(const SphereHierarchy& h) {
  std::vector<glm::dvec3> out;
  for (const SphereNode& n : h.nodes) out.push_back(n.centre);
  return out;
}

double area(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  return 0.5 * glm::length(glm::cross(b - a, c - a));
}

TEST(ParryFaces, ABoxWithARecessedWindowIsElevenFacesAndTheRecessBelongsToItsWall) {
  const Mesh box = boxWithRecessedWindow();
  const FaceSegmentation seg = segmentFaces(box);
  ASSERT_EQ(seg.faces.size(), 11u);
  // Triangles 10..17 are the wall's four quads: one face, which no other triangle joins.
  const std::uint32_t wall = seg.faceOf[10];
  for (std::size_t t = 10; t < 18; ++t) EXPECT_EQ(seg.faceOf[t], wall);
  for (std::size_t t = 0; t < seg.faceOf.size(); ++t)
    if (t < 10 || t >= 18) {
      EXPECT_NE(seg.faceOf[t], wall) << t;
    }
  EXPECT_NEAR(seg.faces[wall].area, 96.0, 1e-9);
  // Each recess quad is a face of its own, and so is each other side of the box.
  for (std::size_t q = 0; q < 14; ++q) {
    if (q >= 5 && q < 9) continue;
    EXPECT_EQ(seg.faceOf[2 * q], seg.faceOf[2 * q + 1]) << q;
    EXPECT_EQ(seg.faces[seg.faceOf[2 * q]].triangles, 2u) << q;
  }
  const std::vector<std::uint32_t> facade = facadesOf(box, seg, UpAxis::Z);
  EXPECT_EQ(facade[seg.faceOf[0]], kFacadeUnderside);
  EXPECT_EQ(facade[seg.faceOf[2]], kFacadeRoof);
  const std::set<std::uint32_t> sides = {facade[seg.faceOf[4]], facade[seg.faceOf[6]],
                                         facade[seg.faceOf[8]], facade[wall]};
  EXPECT_EQ(sides.size(), 4u);  // four sides, four facades
  for (std::uint32_t s : sides) EXPECT_LT(s, kFacadeSides);
  // The back, sill, lintel and both sides of the recess go with the wall, though the sill faces
  // up, the lintel down and the sides along x.
  for (std::size_t q = 9; q < 14; ++q) EXPECT_EQ(facade[seg.faceOf[2 * q]], facade[wall]) << q;
}

TEST(ParryFaces, ACurvedFrontBecomesFacesOfBoundedTurn) {
  // A half cylinder of 36 segments: 20 degrees per face at most, so at least 9 faces.
  Mesh m;
  for (int i = 0; i <= 36; ++i) {
    const double a = M_PI * i / 36;
    m.positions.emplace_back(std::cos(a), std::sin(a), 0.0);
    m.positions.emplace_back(std::cos(a), std::sin(a), 1.0);
  }
  for (std::uint32_t i = 0; i < 36; ++i) {
    const std::uint32_t a = 2 * i, b = a + 1, c = a + 2, d = a + 3;
    m.indices.insert(m.indices.end(), {a, c, d, a, d, b});
  }
  const FaceSegmentation seg = segmentFaces(m);
  EXPECT_GE(seg.faces.size(), 9u);
  EXPECT_LE(seg.faces.size(), 36u);
}

TEST(SphereHierarchy, ParentsHoldTheAverageOfTheirChildrenAndSpheresThatHoldTheirs) {
  const Mesh grid = flatGrid(7, 5, 7.0, 5.0);
  std::vector<SphereVertex> vs(grid.positions.size());
  for (std::size_t v = 0; v < vs.size(); ++v)
    vs[v].position = grid.positions[v], vs[v].radius = 0.5;
  const SphereHierarchy h = buildSphereHierarchy(vs);
  ASSERT_EQ(h.leafCount, vs.size());
  ASSERT_EQ(h.nodes.size(), 2 * vs.size() - 1);  // one tree, binary
  ASSERT_EQ(h.roots.size(), 1u);
  for (std::size_t n = h.leafCount; n < h.nodes.size(); ++n) {
    const SphereNode& p = h.nodes[n];
    ASSERT_FALSE(p.isLeaf());
    for (std::uint32_t c : p.child) {
      ASSERT_LT(c, n);  // children before parents
      EXPECT_EQ(h.nodes[c].parent, n);
      EXPECT_LE(glm::length(h.nodes[c].centre - p.centre) + h.nodes[c].radius, p.radius + 1e-12);
    }
    const glm::dvec3 mean = 0.5 * (h.nodes[p.child[0]].centre + h.nodes[p.child[1]].centre);
    EXPECT_EQ(p.centre, mean);
  }
}

TEST(SphereHierarchy, ACornerMergeStandsAtTheCornerHoldsBothAndCombinesAfterTheForest) {
  // A run of three vertices on a line (one group) between two corners.
  std::vector<SphereVertex> vs(5);
  for (std::size_t v = 0; v < vs.size(); ++v) {
    vs[v].position = glm::dvec3(double(v), 0.0, 0.0);
    vs[v].radius = 0.5;
    vs[v].group = 7;
    vs[v].silhouette = v == 0 || v == 4;
  }
  SphereHierarchy h = buildSphereHierarchy(vs);
  ASSERT_EQ(h.roots.size(), 3u);
  const std::uint32_t run = h.roots.back();
  const std::size_t forest = h.nodes.size();
  const std::pair<std::uint32_t, std::uint32_t> merge[] = {{run, 4u}};
  mergeIntoCorners(h, merge);
  ASSERT_EQ(h.nodes.size(), forest + 1);
  EXPECT_EQ(h.merges, 1u);
  const SphereNode& p = h.nodes.back();
  EXPECT_EQ(p.centre, glm::dvec3(4, 0, 0));  // the corner does not move
  for (std::uint32_t c : p.child) {
    EXPECT_EQ(h.nodes[c].parent, forest);
    EXPECT_LE(glm::length(h.nodes[c].centre - p.centre) + h.nodes[c].radius, p.radius + 1e-12);
  }
  EXPECT_EQ(std::set<std::uint32_t>(h.roots.begin(), h.roots.end()),
            (std::set<std::uint32_t>{0u, std::uint32_t(forest)}));
  // A strip along the line: the run's own combinations decimate first, the merge last, though
  // its sphere is no larger than theirs would allow in any order.
  std::vector<std::uint32_t> strip;
  for (std::uint32_t v = 0; v + 1 < 5; ++v) strip.insert(strip.end(), {v, v + 1, v});
  const SimplificationArrays a = buildSimplificationArrays(h, strip);
  ASSERT_EQ(a.vertices.size(), 2 * (h.nodes.size() - h.leafCount));
  EXPECT_EQ(h.nodes[a.vertices[a.vertices.size() - 2]].parent, forest);
}

TEST(ParryPiece, ADetailStandingFreeOfItsFaceSimplifiesAwayWhole) {
  // A 10 x 10 roof and, on it, a rooftop unit: a box of 0.2 m without a bottom, its own
  // vertices (it touches the roof, shares none of its positions), 0.2% of the area.
  Mesh m = flatGrid(10, 10, 10.0, 10.0);
  using V = glm::dvec3;
  const double a = 5.03, b = 5.23, h = 0.2;                    // off the grid's lines
  addQuad(m, V(a, a, h), V(b, a, h), V(b, b, h), V(a, b, h));  // top
  addQuad(m, V(a, a, 0), V(b, a, 0), V(b, a, h), V(a, a, h));  // -y
  addQuad(m, V(b, a, 0), V(b, b, 0), V(b, b, h), V(b, a, h));  // +x
  addQuad(m, V(b, b, 0), V(a, b, 0), V(a, b, h), V(b, b, h));  // +y
  addQuad(m, V(a, b, 0), V(a, a, 0), V(a, a, h), V(a, b, h));  // -x
  m = weldVertices(m);
  const ParryPiece piece = organisePiece(m);
  const Mesh coarsest = pieceAt(m, piece, 0);
  // Before the detail was one group, each of its faces kept a vertex and the box a few triangles.
  for (std::uint32_t v : coarsest.indices) EXPECT_EQ(coarsest.positions[v].z, 0.0);
  EXPECT_EQ(coarsest.triangleCount(), 4u);  // the roof, as the rectangle above
}

TEST(SphereHierarchy, SilhouetteVerticesAreRootsOfTheirOwnAndGroupsNeverMix) {
  std::vector<SphereVertex> vs(12);
  for (std::size_t v = 0; v < vs.size(); ++v) {
    vs[v].position = glm::dvec3(double(v), 0.0, 0.0);
    vs[v].group = v < 6 ? 1 : 2;
    vs[v].silhouette = v % 4 == 0;  // 0, 4, 8
  }
  const SphereHierarchy h = buildSphereHierarchy(vs);
  EXPECT_EQ(h.roots.size(), 5u);  // three silhouettes, two groups
  for (std::uint32_t v : {0u, 4u, 8u}) EXPECT_EQ(h.nodes[v].parent, kNoSphere);
  // Every leaf under a group's root is of that group.
  for (std::uint32_t r : h.roots) {
    std::vector<std::uint32_t> stack{r}, groups;
    while (!stack.empty()) {
      const std::uint32_t n = stack.back();
      stack.pop_back();
      if (h.nodes[n].isLeaf())
        groups.push_back(vs[n].group);
      else
        stack.insert(stack.end(), {h.nodes[n].child[0], h.nodes[n].child[1]});
    }
    EXPECT_TRUE(std::all_of(groups.begin(), groups.end(),
                            [&](std::uint32_t g) { return g == groups.front(); }));
  }
}

TEST(SphereHierarchy, TheTreeDependsOnThePositionsNotTheirOrder) {
  std::vector<SphereVertex> vs(40);
  for (std::size_t v = 0; v < vs.size(); ++v)
    vs[v].position = glm::dvec3(0.25 * double(v % 7), 0.5 * double(v / 7), 0.0);
  std::vector<SphereVertex> shuffled = vs;
  std::mt19937 rng(3);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  const SphereHierarchy a = buildSphereHierarchy(vs), b = buildSphereHierarchy(shuffled);
  std::vector<std::pair<double, glm::dvec3>> na, nb;
  for (std::size_t n = a.leafCount; n < a.nodes.size(); ++n)
    na.emplace_back(a.nodes[n].radius, a.nodes[n].centre);
  for (std::size_t n = b.leafCount; n < b.nodes.size(); ++n)
    nb.emplace_back(b.nodes[n].radius, b.nodes[n].centre);
  const auto order = [](const auto& x, const auto& y) {
    return std::tie(x.first, x.second.x, x.second.y) < std::tie(y.first, y.second.x, y.second.y);
  };
  std::sort(na.begin(), na.end(), order);
  std::sort(nb.begin(), nb.end(), order);
  EXPECT_EQ(na, nb);
}

TEST(SimplificationArrays, CombiningTheTwoEndsOfAnEdgeDecimatesItsTwoTrianglesAndNoEdgeNone) {
  // A quad a b c d split along a-c, and a far vertex e joined to nothing.
  std::vector<SphereVertex> vs(5);
  vs[0].position = {0, 0, 0};
  vs[1].position = {1, 0, 0};
  vs[2].position = {1, 1, 0};
  vs[3].position = {0, 1, 0};
  vs[4].position = {50, 50, 0};
  const SphereHierarchy h = buildSphereHierarchy(vs);
  const std::vector<std::uint32_t> indices = {0, 1, 2, 0, 2, 3};
  const SimplificationArrays a = buildSimplificationArrays(h, indices);
  ASSERT_EQ(a.increments.size(), 4u);  // five vertices, one tree: four combinations
  EXPECT_EQ(a.triangleCount(), 2u);
  EXPECT_EQ(a.minTriangles(), 0u);
  std::uint32_t sum = 0;
  for (std::size_t j = 0; j < a.increments.size(); ++j) {
    const std::uint32_t c0 = a.vertices[2 * j], c1 = a.vertices[2 * j + 1];
    EXPECT_EQ(h.nodes[c0].parent, h.nodes[c1].parent);
    EXPECT_LE(a.increments[j], 2u);
    sum += a.increments[j];
  }
  EXPECT_EQ(sum, 2u);
  // Splat sizes grow: the far vertex e combines last, and decimates nothing.
  for (std::size_t j = 1; j < a.increments.size(); ++j)
    EXPECT_LE(h.nodes[h.nodes[a.vertices[2 * j - 2]].parent].radius,
              h.nodes[h.nodes[a.vertices[2 * j]].parent].radius);
  EXPECT_EQ(a.increments.back(), 0u);
  for (std::uint32_t v = 0; v < 5; ++v) EXPECT_EQ(a.references[v], h.roots[0]);
}

// Checks the arrays of one mesh draw exactly n triangles for every n in range, the whole mesh at
// the top, and that a stored cut at any n draws what the whole arrays draw below it.
void expectEveryCountExact(const Mesh& mesh, const std::vector<std::uint8_t>& locked = {}) {
  const ParryPiece piece = organisePiece(mesh, locked);
  const SimplificationArrays& a = piece.arrays;
  const std::size_t full = a.triangleCount();
  ASSERT_EQ(full, mesh.triangleCount());
  const Progression p = progressionOf(piece.hierarchy, a);
  const std::vector<glm::dvec3> at = centres(piece.hierarchy);
  // The original mesh: the leaves stand at their vertices.
  const std::vector<std::uint32_t> all =
      progressiveIndices(a.triangles, p, full, piece.hierarchy.nodes.size());
  EXPECT_EQ(all, a.triangles);
  EXPECT_EQ(triangleSet(at, all), triangleSet(mesh.positions, mesh.indices));
  for (std::size_t n = a.minTriangles(); n <= full; ++n) {
    const std::vector<std::uint32_t> idx =
        progressiveIndices(a.triangles, p, n, piece.hierarchy.nodes.size());
    ASSERT_EQ(idx.size(), 3 * n) << n;
    // Triangles of no area: only those of a combination that straddles the cut, inside it.
    std::size_t flat = 0, before = 0, straddling = 0;
    for (std::size_t i = 0; i < idx.size(); i += 3)
      flat += idx[i] == idx[i + 1] || idx[i + 1] == idx[i + 2] || idx[i] == idx[i + 2];
    for (std::uint32_t inc : a.increments) {
      if (before < full - n && before + inc > full - n) straddling = before + inc - (full - n);
      before += inc;
    }
    EXPECT_EQ(flat, straddling) << n;
  }
  for (std::size_t n : {full, (full + a.minTriangles()) / 2, a.minTriangles()}) {
    const ProgressiveCut cut = cutArrays(piece.hierarchy, a, n);
    const std::size_t stored = cut.indices.size() / 3;
    for (std::size_t m = stored - cut.progression.decimated(); m <= stored; ++m) {
      const std::vector<std::uint32_t> local =
          progressiveIndices(cut.indices, cut.progression, m, cut.vertices.size());
      std::vector<std::uint32_t> spheres;
      for (std::uint32_t v : local) spheres.push_back(cut.vertices[v]);
      const std::vector<std::uint32_t> whole =
          progressiveIndices(a.triangles, p, m, piece.hierarchy.nodes.size());
      EXPECT_EQ(triangleSet(at, spheres), triangleSet(at, whole)) << n << " " << m;
    }
  }
}

TEST(SimplificationArrays, GiveExactlyNTrianglesForEveryNAndTheOriginalMeshAtFull) {
  expectEveryCountExact(flatGrid(9, 6, 9.0, 6.0));
  expectEveryCountExact(boxWithRecessedWindow());  // all corners: nothing to combine
  expectEveryCountExact(testmesh::sphere(10, 20));
  expectEveryCountExact(testmesh::wavyGrid(12));
}

TEST(ParryPiece, SilhouetteVerticesSurviveToTheCoarsestLevelAndTheFaceKeepsItsOutline) {
  const Mesh grid = flatGrid(10, 4, 10.0, 4.0);
  const ParryPiece piece = organisePiece(grid);
  EXPECT_EQ(piece.faces.faces.size(), 1u);
  double error = -1.0;
  const Mesh coarsest = pieceAt(grid, piece, 0, &error);
  EXPECT_EQ(coarsest.triangleCount(), piece.arrays.minTriangles());
  // The face as the polygon of its corners: each straight run of the outline combined into a
  // corner at its end, the inside into one vertex, a fan of four triangles (eight, a vertex in
  // the middle of each side too, before the runs' roots combined into the corners).
  EXPECT_EQ(coarsest.triangleCount(), 4u);
  EXPECT_GT(error, 0.5);
  // The four corners are silhouette vertices and stand where they were.
  for (glm::dvec3 c :
       {glm::dvec3(0, 0, 0), glm::dvec3(10, 0, 0), glm::dvec3(10, 4, 0), glm::dvec3(0, 4, 0)})
    EXPECT_NE(std::find(coarsest.positions.begin(), coarsest.positions.end(), c),
              coarsest.positions.end());
  // Every vertex stays in the face's plane, inside it, and outline vertices on the outline.
  for (const glm::dvec3& p : coarsest.positions) {
    EXPECT_EQ(p.z, 0.0);
    EXPECT_TRUE(p.x >= 0.0 && p.x <= 10.0 && p.y >= 0.0 && p.y <= 4.0);
  }
  // No holes: the coarsest triangles cover the rectangle (each of a grid of points lies in one),
  // and their area adds up to it.
  double sum = 0.0;
  for (std::size_t i = 0; i < coarsest.indices.size(); i += 3)
    sum +=
        area(coarsest.positions[coarsest.indices[i]], coarsest.positions[coarsest.indices[i + 1]],
             coarsest.positions[coarsest.indices[i + 2]]);
  EXPECT_NEAR(sum, 40.0, 1e-9);
}

TEST(ParryPiece, LockedVerticesAreNeverCombinedSoNeighbouringPiecesMeet) {
  const Mesh grid = flatGrid(8, 8, 8.0, 8.0);
  std::vector<std::uint8_t> locked(grid.positions.size(), 0);
  // The middle column of vertices, as if the piece met another there.
  for (std::size_t v = 0; v < grid.positions.size(); ++v)
    if (grid.positions[v].x == 4.0) locked[v] = 1;
  const ParryPiece piece = organisePiece(grid, locked);
  const Mesh coarsest = pieceAt(grid, piece, 0);
  for (std::size_t v = 0; v < grid.positions.size(); ++v) {
    if (!locked[v]) continue;
    EXPECT_EQ(piece.silhouette[piece.positionOf[v]], 1);
    EXPECT_NE(std::find(coarsest.positions.begin(), coarsest.positions.end(), grid.positions[v]),
              coarsest.positions.end());
  }
}

TEST(ParrySimplifier, HitsTheTargetAndKeepsTheProgressionDownToTheOutlines) {
  auto simplifier = makeSimplifier("parry");
  ASSERT_TRUE(simplifier);
  const Mesh grid = flatGrid(20, 20, 20.0, 20.0);
  const SimplifiedMesh s = (*simplifier)->simplify(grid, 200);
  EXPECT_NEAR(double(s.mesh.triangleCount()), 200.0, 10.0);
  EXPECT_FALSE(s.mesh.progression.empty());
  EXPECT_LT(s.mesh.triangleCount() - s.mesh.progression.decimated(), 16u);
  EXPECT_GT(s.geometricError, 0.0);
  for (std::uint32_t v : s.mesh.indices) ASSERT_LT(v, s.mesh.positions.size());
  for (std::uint32_t v : s.mesh.progression.moves) ASSERT_LT(v, s.mesh.positions.size());
}

// A flat grid whose inner vertices are moved at random by up to 0.15 of a cell (no triangle of
// the grid turns over): vertex clustering folds some of its triangles over.
Mesh jitteredGrid(int n, std::uint32_t seed) {
  Mesh m = flatGrid(n, n, double(n), double(n));
  m.name = "jittered grid " + std::to_string(seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  for (glm::dvec3& p : m.positions)
    if (p.x > 0.0 && p.x < n && p.y > 0.0 && p.y < n)
      p += glm::dvec3(jitter(rng), jitter(rng), 0.0);
  return m;
}

// Every count of the piece's progression (the node's own triangles at that count, as a store
// keeps them) has no triangle facing against the surface it stands for.
void expectNoTriangleFacesAway(const Mesh& mesh) {
  const ParryPiece piece = organisePiece(mesh);
  for (std::size_t n = piece.arrays.minTriangles(); n <= mesh.triangleCount(); ++n) {
    const Mesh at = pieceAt(mesh, piece, n);
    const auto report = metrics::checkFacing(mesh, at, 1e9);
    ASSERT_TRUE(report) << report.error().message;
    ASSERT_EQ(report->flipped, 0u)
        << mesh.name << " at " << n << " of " << mesh.triangleCount() << " triangles";
  }
}

TEST(ParryPiece, ClusteringNeverLeavesATriangleFacingAwayFromItsSurface) {
  for (std::uint32_t seed : {1u, 2u, 3u}) expectNoTriangleFacesAway(jitteredGrid(12, seed));
  expectNoTriangleFacesAway(testmesh::wavyGrid(12));
}

}  // namespace
}  // namespace hlod
