// The procedural power plant (hlod/plant/PowerPlant.h) and the GLB writer: byte-identical for a
// seed, and the file imports as the objects and triangles the generator says it made.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "ImportTestUtil.h"
#include "hlod/import/Import.h"
#include "hlod/plant/GlbWriter.h"
#include "hlod/plant/PowerPlant.h"

using namespace hlod;

namespace {

PlantOptions small(std::uint64_t seed) {
  PlantOptions o;
  o.objects = 1;  // one unit and its rack
  o.seed = seed;
  o.detail = 0.25;
  return o;
}

}  // namespace

TEST(PowerPlant, IsByteIdenticalForTheSameSeedAndDiffersForAnother) {
  const auto a = encodeGlb(makePowerPlant(small(7)).scene);
  const auto b = encodeGlb(makePowerPlant(small(7)).scene);
  const auto c = encodeGlb(makePowerPlant(small(8)).scene);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_EQ(*a, *b);
  EXPECT_NE(*a, *c);
  // A GLB: the header's magic, version 2 and total length.
  ASSERT_GE(a->size(), 28u);
  EXPECT_EQ(a->compare(0, 4, "glTF"), 0);
  std::uint32_t version = 0, length = 0;
  std::memcpy(&version, a->data() + 4, 4);
  std::memcpy(&length, a->data() + 8, 4);
  EXPECT_EQ(version, 2u);
  EXPECT_EQ(length, a->size());
}

TEST(PowerPlant, ImportsAsTheObjectsAndTrianglesItMade) {
  hlod::testing::TempDir dir;
  const Plant plant = makePowerPlant(small(1));
  ASSERT_TRUE(writeGlb(plant.scene, dir.file("plant.glb")).ok());
  auto model = importModel(dir.file("plant.glb"));
  ASSERT_TRUE(model.ok()) << model.message();
  EXPECT_EQ(model->objectCount(), plant.summary.objects);
  EXPECT_EQ(model->triangleCount(), plant.summary.triangles);
  EXPECT_GT(plant.summary.objects, 1000u);  // thousands of parts, most of them small
  EXPECT_GE(plant.summary.byType.at("bolt").first, plant.summary.objects / 3);
  // The long runs span the site: each run's object is as wide as the racks.
  const Aabb site = model->bounds();
  EXPECT_NEAR(site.size().x, plant.summary.bounds.size().x, 1e-3 * site.size().x + 1e-3);
  EXPECT_EQ(plant.summary.pipeRuns, 13u);
  // Y up, metres: the ground at 0, the boilers' domes above 30 m.
  EXPECT_NEAR(site.min.y, 0.0, 1e-6);
  EXPECT_GT(site.max.y, 30.0);
}

TEST(PowerPlant, ObjectsScaleTheSite) {
  PlantOptions o = small(1);
  o.objects = 8000;
  const Plant bigger = makePowerPlant(o);
  const Plant one = makePowerPlant(small(1));
  EXPECT_EQ(bigger.summary.units, 4u);
  EXPECT_EQ(one.summary.units, 1u);
  EXPECT_GT(bigger.summary.objects, 3 * one.summary.objects);
  EXPECT_LT(bigger.summary.objects, 5 * one.summary.objects);
}
