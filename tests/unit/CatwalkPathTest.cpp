// The catwalk walk and the fly-around (hlod/runtime/CatwalkPath.h, CameraPath.h) on the power
// plant: every frame of the walk is at eye height over a catwalk and clear of every triangle
// (never through a pipe, a wall or a railing), and the fly-around stays outside the model.
#include <gtest/gtest.h>

#include "ImportTestUtil.h"
#include "hlod/import/Import.h"
#include "hlod/metrics/TriangleBvh.h"
#include "hlod/plant/PowerPlant.h"
#include "hlod/runtime/CatwalkPath.h"

using namespace hlod;

namespace {

// A small plant (one unit and its rack), as imported from its GLB.
const Model& smallPlant() {
  static const Model model = [] {
    hlod::testing::TempDir dir;
    PlantOptions o;
    o.objects = 1;
    o.detail = 0.25;
    EXPECT_TRUE(writeGlb(makePowerPlant(o).scene, dir.file("plant.glb")).ok());
    auto m = importModel(dir.file("plant.glb"));
    EXPECT_TRUE(m.ok()) << m.message();
    return m.ok() ? std::move(*m) : Model{};
  }();
  return model;
}

TriangleSource trianglesOf(const Model& model) {
  return [&model](const TriangleVisitor& visit) -> Status {
    for (const Mesh& m : model.meshes)
      for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3)
        visit(m.positions[m.indices[i]], m.positions[m.indices[i + 1]],
              m.positions[m.indices[i + 2]]);
    return Ok{};
  };
}

metrics::TriangleBvh bvhOf(const Model& model) {
  std::vector<metrics::Triangle> triangles;
  for (const Mesh& m : model.meshes)
    for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3)
      triangles.push_back({m.positions[m.indices[i]], m.positions[m.indices[i + 1]],
                           m.positions[m.indices[i + 2]]});
  return metrics::TriangleBvh(std::move(triangles));
}

}  // namespace

TEST(CatwalkPath, WalksTheCatwalksAtEyeHeightClearOfEveryTriangle) {
  const Model& plant = smallPlant();
  ASSERT_FALSE(plant.meshes.empty());
  const CatwalkOptions options;
  auto path = makeCatwalkPath(trianglesOf(plant), plant.bounds(), UpAxis::Y, options);
  ASSERT_TRUE(path.ok()) << path.message();
  EXPECT_GT(path->duration(), 20.0);
  EXPECT_LE(path->duration(), options.duration + 30.0);
  const metrics::TriangleBvh bvh = bvhOf(plant);
  double nearest = 1e9, lowest = 1e9;
  std::size_t frames = 0;
  for (const CameraSample& s : path->sampleAt(30.0)) {
    const glm::dvec3 eye = s.camera.position;
    lowest = std::min(lowest, eye.y);
    // The eye and the body below it (chest, knees) are clear of every triangle.
    for (double below : {0.0, 0.6, 1.2})
      nearest = std::min(nearest, bvh.distance(eye - glm::dvec3(0.0, below, 0.0)));
    ++frames;
  }
  EXPECT_GT(frames, 600u);
  // The clearance is 0.5 m around the walker's floor cells (0.25 m): at least 0.25 m to anything.
  EXPECT_GE(nearest, 0.25);
  // On the catwalks, at eye height: the first is at 7 m.
  EXPECT_GE(lowest, 7.0 + options.eyeHeight - 0.35);
}

TEST(CatwalkPath, AModelWithoutCatwalksIsAnError) {
  Model flat;
  Mesh ground;
  ground.positions = {{0, 0, 0}, {100, 0, 0}, {100, 0, 100}, {0, 0, 100}};
  ground.indices = {0, 2, 1, 0, 3, 2};
  flat.meshes.push_back(ground);
  auto path = makeCatwalkPath(trianglesOf(flat), flat.bounds(), UpAxis::Y);
  ASSERT_FALSE(path.ok());
  EXPECT_NE(path.message().find("no walkable floor"), std::string::npos) << path.message();
}

TEST(FlyAroundPath, StaysOutsideTheModelsBox) {
  Skeleton s;
  NodeInfo root;
  root.bounds.extend({-10.0, 0.0, -20.0});
  root.bounds.extend({50.0, 30.0, 40.0});
  s.nodes.push_back(root);
  s.roots = {0};
  s.up = UpAxis::Y;
  auto path = makeFlyAroundPath(s);
  ASSERT_TRUE(path.ok()) << path.message();
  EXPECT_DOUBLE_EQ(path->duration(), 40.0);
  for (const CameraSample& c : path->sampleAt(10.0)) {
    const glm::dvec3 p = c.camera.position;
    const bool inside =
        p.x > -10.0 && p.x < 50.0 && p.y > 0.0 && p.y < 30.0 && p.z > -20.0 && p.z < 40.0;
    EXPECT_FALSE(inside) << p.x << " " << p.y << " " << p.z;
  }
}
