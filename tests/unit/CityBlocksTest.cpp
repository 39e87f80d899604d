// Buildings grouped into grid blocks (hlod/builder/CityBlocks.h): a building is never split,
// each lies in the block of the cell its footprint centre is in, the cell size is the one asked
// for, and walls shared across a cell border are listed for locking.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "hlod/builder/CityBlocks.h"

using namespace hlod;

namespace {

// Appends an axis-aligned box as city object `object`: its top to mesh 0 (roof), its sides to
// mesh 1 (walls), as the CityJSON reader colours them, with one run per mesh.
void addBuilding(Model& m, std::uint32_t object, glm::dvec3 lo, glm::dvec3 hi) {
  if (m.meshes.size() < 2) m.meshes.resize(2);
  m.meshes[0].baseColor = {0.6f, 0.3f, 0.2f, 1.0f};
  m.meshes[1].baseColor = {0.9f, 0.8f, 0.7f, 1.0f};
  auto quad = [&](int mesh, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 d) {
    Mesh& x = m.meshes[std::size_t(mesh)];
    const auto base = std::uint32_t(x.positions.size());
    for (const auto& p : {a, b, c, d}) x.positions.push_back(p);
    for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) x.indices.push_back(base + i);
  };
  const std::uint32_t roofFirst = std::uint32_t(m.meshes[0].triangleCount());
  const std::uint32_t wallFirst = std::uint32_t(m.meshes[1].triangleCount());
  quad(0, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z});
  quad(1, {lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, {lo.x, lo.y, hi.z});
  quad(1, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, {hi.x, lo.y, hi.z});
  quad(1, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z}, {lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z});
  quad(1, {lo.x, hi.y, lo.z}, {lo.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, hi.z});
  m.objectRuns.push_back({object, 0, roofFirst, 2});
  m.objectRuns.push_back({object, 1, wallFirst, 8});
  m.cityObjects = std::max<std::size_t>(m.cityObjects, object + 1);
}

}  // namespace

TEST(CityBlocks, EachBuildingIsWholeInTheCellOfItsFootprintCentre) {
  Model m;
  m.zUp = true;
  // A row of 12 m buildings every 15 m across several 100 m cells, one straddling x = 100
  // with its centre left of it, one straddling x = 200 with its centre right of it.
  std::uint32_t id = 0;
  for (double x = 5.0; x < 300.0; x += 15.0)
    addBuilding(m, id++, {x, 10.0, 0.0}, {x + 12.0, 30.0, 10.0 + x / 10.0});
  addBuilding(m, id++, {90.0, 50.0, 0.0}, {108.0, 70.0, 12.0});   // centre 99: cell 0
  addBuilding(m, id++, {195.0, 50.0, 0.0}, {215.0, 70.0, 12.0});  // centre 205: cell 2
  const std::vector<BuildingBlock> blocks = groupBuildingsIntoBlocks(m, 100.0);
  ASSERT_EQ(blocks.size(), 3u);
  std::size_t buildings = 0, triangles = 0;
  for (const BuildingBlock& b : blocks) {
    buildings += b.buildings;
    EXPECT_EQ(b.cell.y, 0);
    // Two colours, each a mesh of whole buildings: 2 roof and 8 wall triangles per building.
    ASSERT_EQ(b.model.meshes.size(), 2u);
    EXPECT_EQ(b.model.meshes[0].triangleCount(), 2 * b.buildings);
    EXPECT_EQ(b.model.meshes[1].triangleCount(), 8 * b.buildings);
    triangles += b.model.triangleCount();
    // Every building's footprint centre in the block's cell: each roof quad is one building.
    const Mesh& roofs = b.model.meshes[0];
    for (std::size_t t = 0; t < roofs.triangleCount(); t += 2) {
      Aabb roof;
      for (std::size_t k = 0; k < 6; ++k) roof.extend(roofs.positions[roofs.indices[3 * t + k]]);
      const glm::dvec3 c = roof.centre();
      EXPECT_GE(c.x, 100.0 * double(b.cell.x));
      EXPECT_LT(c.x, 100.0 * double(b.cell.x + 1));
      // Its walls are here too: the block's box holds the whole building.
      const Aabb box = b.model.meshes[1].bounds();
      EXPECT_LE(box.min.x, roof.min.x);
      EXPECT_GE(box.max.x, roof.max.x);
    }
  }
  EXPECT_EQ(buildings, std::size_t(id));
  EXPECT_EQ(triangles, m.triangleCount());
  EXPECT_EQ(blocks[0].cell.x, 0);
  EXPECT_EQ(blocks[1].cell.x, 1);
  EXPECT_EQ(blocks[2].cell.x, 2);
  // The building straddling x = 100 went whole to cell 0: its far corner is in block 0.
  EXPECT_GE(blocks[0].model.bounds().max.x, 108.0);
}

TEST(CityBlocks, TheCellSizeDecidesHowManyBlocks) {
  Model m;
  std::uint32_t id = 0;
  for (double x = 0.0; x < 400.0; x += 20.0)
    for (double y = 0.0; y < 400.0; y += 20.0)
      addBuilding(m, id++, {x + 2.0, y + 2.0, 0.0}, {x + 18.0, y + 18.0, 9.0});
  EXPECT_EQ(groupBuildingsIntoBlocks(m, 100.0).size(), 16u);
  EXPECT_EQ(groupBuildingsIntoBlocks(m, 200.0).size(), 4u);
  EXPECT_EQ(groupBuildingsIntoBlocks(m, 1000.0).size(), 1u);
  EXPECT_EQ(groupBuildingsIntoBlocks(m, 20.0).size(), 400u);
  // Rows south to north, then west to east.
  const auto blocks = groupBuildingsIntoBlocks(m, 200.0);
  EXPECT_EQ(blocks[1].cell, glm::i64vec2(1, 0));
  EXPECT_EQ(blocks[2].cell, glm::i64vec2(0, 1));
}

TEST(CityBlocks, WallsSharedAcrossACellBorderAreListedInBothBlocks) {
  Model m;
  addBuilding(m, 0, {80.0, 0.0, 0.0}, {100.0, 20.0, 10.0});   // ends at x = 100
  addBuilding(m, 1, {100.0, 0.0, 0.0}, {120.0, 20.0, 10.0});  // starts there
  addBuilding(m, 2, {150.0, 0.0, 0.0}, {160.0, 20.0, 10.0});  // alone
  const auto blocks = groupBuildingsIntoBlocks(m, 100.0);
  ASSERT_EQ(blocks.size(), 2u);
  for (const BuildingBlock& b : blocks) {
    EXPECT_EQ(b.shared.size(), 4u);  // the party wall's corners
    for (const glm::dvec3& p : b.shared) EXPECT_EQ(p.x, 100.0);
  }
}

TEST(CityBlocks, AModelWithoutCityObjectsIsOneBlock) {
  Model m;
  addBuilding(m, 0, {0.0, 0.0, 0.0}, {500.0, 20.0, 10.0});
  addBuilding(m, 1, {900.0, 0.0, 0.0}, {950.0, 20.0, 10.0});
  m.objectRuns.clear();
  const auto blocks = groupBuildingsIntoBlocks(m, 100.0);
  ASSERT_EQ(blocks.size(), 1u);
  EXPECT_EQ(blocks[0].model.triangleCount(), m.triangleCount());
}
