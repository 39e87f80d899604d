// Import of the real meshes in shared/data (made by others, not by us): exact triangle counts,
// finite bounds, and the import time printed for the report.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "SharedData.h"
#include "hlod/import/Import.h"

namespace hlod {
namespace {

// Imports a shared file (skipping when absent) and checks what every good import must give.
Result<Model> importShared(const std::string& name) {
  const auto path = test::sharedData(name);
  const auto start = std::chrono::steady_clock::now();
  auto model = importModel(path);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (model.ok()) {
    std::printf("[ import   ] %s: %zu meshes, %zu triangles in %.1f ms\n", name.c_str(),
                model->meshes.size(), model->triangleCount(), ms);
    const Aabb b = model->bounds();
    EXPECT_FALSE(b.empty()) << name;
    for (int i = 0; i < 3; ++i) {
      EXPECT_TRUE(std::isfinite(b.min[i]) && std::isfinite(b.max[i])) << name;
      EXPECT_LT(b.min[i], b.max[i]) << name;
    }
  }
  return model;
}

TEST(RealDataImport, ReadsStanfordBunnyOff) {
  SKIP_IF_SHARED_ABSENT("bunny00.off");
  auto model = importShared("bunny00.off");
  ASSERT_TRUE(model.ok()) << model.message();
  ASSERT_EQ(model->meshes.size(), 1u);
  EXPECT_EQ(model->meshes[0].positions.size(), 37706u);
  EXPECT_EQ(model->triangleCount(), 75408u);
}

TEST(RealDataImport, ReadsElephantAndArmadilloOff) {
  SKIP_IF_SHARED_ABSENT("refined_elephant.off");
  SKIP_IF_SHARED_ABSENT("armadillo.off");
  auto elephant = importShared("refined_elephant.off");
  ASSERT_TRUE(elephant.ok()) << elephant.message();
  EXPECT_EQ(elephant->meshes[0].positions.size(), 44460u);
  EXPECT_EQ(elephant->triangleCount(), 88928u);
  auto armadillo = importShared("armadillo.off");
  ASSERT_TRUE(armadillo.ok()) << armadillo.message();
  EXPECT_EQ(armadillo->meshes[0].positions.size(), 26002u);
  EXPECT_EQ(armadillo->triangleCount(), 52000u);
}

TEST(RealDataImport, ReadsBinaryStlHeadAndMergesCorners) {
  SKIP_IF_SHARED_ABSENT("head.stl");
  auto model = importShared("head.stl");
  ASSERT_TRUE(model.ok()) << model.message();
  EXPECT_EQ(model->triangleCount(), 117694u);
  // A closed surface has about half as many vertices as triangles; unmerged would be 3x.
  EXPECT_LT(model->meshes[0].positions.size(), 117694u);
}

TEST(RealDataImport, ReadsTwoCylinderEngineGlb) {
  SKIP_IF_SHARED_ABSENT("2CylinderEngine.glb");
  auto model = importShared("2CylinderEngine.glb");
  ASSERT_TRUE(model.ok()) << model.message();
  // 29 meshes with 75,730 triangles, instanced by 82 nodes into 115 primitives: every instance
  // is baked with its node transform.
  EXPECT_EQ(model->meshes.size(), 115u);
  EXPECT_EQ(model->triangleCount(), 121496u);
  for (const auto& m : model->meshes) EXPECT_EQ(m.normals.size(), m.positions.size()) << m.name;
}

TEST(RealDataImport, ReadsPeterbiltObjWithMaterials) {
  SKIP_IF_SHARED_ABSENT("peterbilt/peterbilt.obj");
  auto model = importShared("peterbilt/peterbilt.obj");
  ASSERT_TRUE(model.ok()) << model.message();
  EXPECT_EQ(model->triangleCount(), 116501u);
  EXPECT_GT(model->meshes.size(), 1u);
}

}  // namespace
}  // namespace hlod
