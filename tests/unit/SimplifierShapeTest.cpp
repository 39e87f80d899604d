// Coarse levels keep their shape: no simplified triangle faces away from the surface it stands
// for (under back-face culling that is a hole), thin slabs, flat facades and boxes against walls
// stay within the level's error, and vertex clustering leaves no slivers standing off the surface.
#include <cmath>
#include <cstdio>
#include <string>
#include <unordered_map>

#include <gtest/gtest.h>

#include "SimplifierShapeTestMeshes.h"
#include "hlod/builder/Simplifier.h"
#include "hlod/builder/VertexClustering.h"
#include "hlod/metrics/SimplifiedFacing.h"
#include "hlod/metrics/SurfaceDistance.h"

namespace hlod {
namespace {

struct ShapeCase {
  const char* name;
  Mesh (*make)();
  // How far a coarse level may deviate and still have the shape (m): the slab not cut through
  // (half its thickness), the box a box, the facade flat but not folded (its recess depth), the
  // box against the wall still standing (half its depth).
  double keptWithin;
};

const ShapeCase kShapes[] = {
    {"thinSlab", testmesh::thinSlab, 0.075},
    {"box",
     [] {
       return testmesh::griddedBox({0, 0, 0}, {4, 3, 2}, 0.25);
     },
     0.5},
    {"recessedFacade", testmesh::recessedFacade, 0.3 + 1e-9},
    {"boxAgainstWall", testmesh::boxAgainstWall, 1.0},
};

struct Measured {
  std::size_t triangles = 0;
  double geometricError = 0.0;
  double hausdorff = 0.0;
  metrics::FacingReport facing;
};

Measured simplifyAndMeasure(const Simplifier& s, const Mesh& mesh, std::size_t target) {
  const SimplifiedMesh out = s.simplify(weldVertices(mesh), target);
  Measured m;
  m.triangles = out.mesh.triangleCount();
  m.geometricError = out.geometricError;
  auto facing = metrics::checkFacing(mesh, out.mesh, 2.0 * out.geometricError + 1e-6);
  EXPECT_TRUE(facing.ok()) << facing.message();
  if (facing) m.facing = *facing;
  auto d = metrics::surfaceDistance(mesh, out.mesh, 20000);
  EXPECT_TRUE(d.ok()) << d.message();
  if (d) m.hausdorff = d->hausdorff;
  return m;
}

class SimplifierShape : public testing::TestWithParam<const char*> {};
class SimplifierShapeKept : public testing::TestWithParam<const char*> {};

TEST_P(SimplifierShape, NoSimplifiedTriangleFacesAwayFromTheSurfaceItStandsFor) {
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  for (const ShapeCase& c : kShapes) {
    const Mesh mesh = c.make();
#ifdef HLODR_SANITIZE_BUILD
    const std::size_t divisors[] = {16, 256};
#else
    const std::size_t divisors[] = {4, 16, 64, 256};
#endif
    for (std::size_t divisor : divisors) {
      const std::size_t target = std::max<std::size_t>(12, mesh.triangleCount() / divisor);
      const Measured m = simplifyAndMeasure(**simplifier, mesh, target);
      EXPECT_EQ(m.facing.flipped, 0u)
          << c.name << " at " << target << " of " << mesh.triangleCount()
          << " triangles: " << m.triangles << " kept";
    }
  }
}

TEST_P(SimplifierShapeKept, ThinSlabsFacadesAndBoxesAgainstWallsStayWithinTheLevelsError) {
  // Each of these shapes has an exact representation in a few dozen triangles: a coarse level
  // must not cut through the slab, fold the facade or drop the box, and the error it reports
  // must bound what it did (the selector trusts it).
  auto simplifier = makeSimplifier(GetParam());
  ASSERT_TRUE(simplifier);
  for (const ShapeCase& c : kShapes) {
    const Mesh mesh = c.make();
    for (std::size_t divisor : {16, 64}) {
      const std::size_t target = std::max<std::size_t>(12, mesh.triangleCount() / divisor);
      const Measured m = simplifyAndMeasure(**simplifier, mesh, target);
      std::printf(
          "%s %s target %zu: %zu triangles, error %.4g, hausdorff %.4g, flipped %zu, "
          "off %zu (max %.4g)\n",
          GetParam(), c.name, target, m.triangles, m.geometricError, m.hausdorff, m.facing.flipped,
          m.facing.standingOff, m.facing.maxOff);
      EXPECT_LE(m.hausdorff, 2.0 * m.geometricError + 1e-6) << c.name << " at " << target;
      EXPECT_LE(m.hausdorff, c.keptWithin) << c.name << " at " << target;
      // The guard may keep more than asked where the shape needs it, within half again.
      EXPECT_LE(m.triangles, target + target / 2 + 12) << c.name;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(BothSimplifiers, SimplifierShape, testing::Values("meshopt", "openmesh"));

// The shape test for the default simplifier. OpenMesh's decimater still drops a box standing
// against a wall (Hausdorff 5 m of a 2 m box at 84 triangles) and folds the facade (1.9 m at 42):
// not yet fixed.
INSTANTIATE_TEST_SUITE_P(Meshopt, SimplifierShapeKept, testing::Values("meshopt"));

// The shape the simplifiers see: one vertex per position.
Simplifier::Shape shapeOf(const Mesh& mesh) {
  Simplifier::Shape shape;
  std::unordered_map<std::string, std::uint32_t> index;
  std::vector<std::uint32_t> remap(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::dvec3 p = mesh.positions[v] + glm::dvec3(0.0);
    const std::string key(reinterpret_cast<const char*>(&p), sizeof p);
    auto [it, fresh] = index.try_emplace(key, std::uint32_t(shape.positions.size()));
    if (fresh) shape.positions.push_back(p), shape.locked.push_back(0);
    remap[v] = it->second;
  }
  for (std::uint32_t i : mesh.indices) shape.indices.push_back(remap[i]);
  return shape;
}

// A disc of 25,000 triangles around one centre vertex: OpenMesh's collapse checks cost the
// valence of their ends, and at the centre the decimation ran for over five minutes (meshopt:
// under a second). The centre is split for OpenMesh into copies of bounded valence: the fan
// simplifies like any surface, and stays a whole, flat disc.
TEST(OpenMeshSimplifier, AFanAroundOneVertexSimplifiesAndStaysWhole) {
  constexpr int kRim = 25000;
  Mesh fan;
  fan.positions.push_back({0.0, 0.0, 0.0});
  for (int i = 0; i < kRim; ++i) {
    const double a = 2.0 * 3.14159265358979 * i / kRim;
    fan.positions.push_back({10.0 * std::cos(a), 10.0 * std::sin(a), 0.0});
  }
  for (int i = 0; i < kRim; ++i)
    fan.indices.insert(fan.indices.end(),
                       {0u, std::uint32_t(1 + i), std::uint32_t(1 + (i + 1) % kRim)});
  auto simplifier = makeSimplifier("openmesh");
  ASSERT_TRUE(simplifier.ok());
  const SimplifiedMesh out = (*simplifier)->simplify(fan, 500);
  EXPECT_LE(out.mesh.triangleCount(), 1000u);
  EXPECT_GT(out.mesh.triangleCount(), 0u);
  double area = 0.0;
  for (std::size_t t = 0; t + 2 < out.mesh.indices.size(); t += 3) {
    const glm::dvec3 a = out.mesh.positions[out.mesh.indices[t]];
    const glm::dvec3 b = out.mesh.positions[out.mesh.indices[t + 1]];
    const glm::dvec3 c = out.mesh.positions[out.mesh.indices[t + 2]];
    EXPECT_GT(glm::cross(b - a, c - a).z, 0.0);  // none flipped, none without area
    area += 0.5 * glm::cross(b - a, c - a).z;
  }
  // The disc's area, less what the simplified rim cuts off (a 500-gon loses 0.003%).
  EXPECT_NEAR(area, 3.14159265 * 100.0, 0.02 * 3.14159265 * 100.0);
}

TEST(VertexClustering, LeavesNoSliverStandingOffTheSurfaceOrFacingAway) {
  // Clustering a cell that holds both sides of a thin slab, or a wall and the box against it,
  // joins vertices of different surfaces: the triangles between them stand across the gap
  // (shards) or face the wrong way (holes).
  for (const ShapeCase& c : kShapes) {
    const Mesh mesh = c.make();
    const Simplifier::Shape shape = shapeOf(mesh);
    for (std::size_t divisor : {8, 32, 128}) {
      const std::size_t target = std::max<std::size_t>(12, mesh.triangleCount() / divisor);
      const Simplifier::ReducedShape r = clusterVertices(shape, shape.indices, target);
      Mesh out;
      out.positions = shape.positions;
      out.indices = r.indices;
      ASSERT_GT(out.triangleCount(), 0u) << c.name;
      EXPECT_LE(out.triangleCount(), target) << c.name;
      auto facing = metrics::checkFacing(mesh, out, r.geometricError + 1e-6);
      ASSERT_TRUE(facing.ok()) << facing.message();
      std::printf(
          "cluster %s target %zu: %zu triangles, error %.4g, flipped %zu, off %zu "
          "(max %.4g)\n",
          c.name, target, out.triangleCount(), r.geometricError, facing->flipped,
          facing->standingOff, facing->maxOff);
      // Clustering alone may leave a few folds where a recess's reveals meet the wall (the
      // simplifiers' guard turns those); before facing-aware clusters a slab's top and bottom
      // merged and a third of its triangles faced down.
      EXPECT_LE(facing->flipped, 1 + out.triangleCount() / 50) << c.name << " at " << target;
      EXPECT_EQ(facing->standingOff, 0u) << c.name << " at " << target;
    }
  }
}

}  // namespace
}  // namespace hlod
