// Cell nodes above the blocks (builder/CellNodes.h): the store they make, their flat colours, what
// the skeleton decoder refuses of them, and the front a selector draws from them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <tuple>

#include "ImportTestUtil.h"
#include "RuntimeTestScene.h"
#include "builder/BorderStitching.h"
#include "builder/BuildingBoxes.h"
#include "builder/CellColours.h"
#include "builder/CellNodes.h"
#include "builder/OuterSides.h"
#include "builder/Preprocess.h"
#include "builder/Underlay.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/city/City.h"
#include "hlod/runtime/Selector.h"
#include "hlod/store/NodeStore.h"

using namespace hlod;

namespace {

// A city of four blocks with small textures, built once with cell nodes and once without.
struct CellCity {
  hlod::testing::TempDir dir;
  std::unique_ptr<NodeStore> cells, plain;
  CellCity() {
    CityOptions city;
    city.blocks = 4;
    city.textureSize = 64;
    EXPECT_TRUE(writeCity(dir.file("city"), city).ok());
    BuildOptions options;
    options.cells = CellMode::On;
    EXPECT_TRUE(buildStoreFromCity(dir.file("city"), dir.file("cells.hlod"), options).ok());
    options.cells = CellMode::Auto;  // 4 blocks' hlod_0 is far under kCellTriangles
    EXPECT_TRUE(buildStoreFromCity(dir.file("city"), dir.file("plain.hlod"), options).ok());
    cells = std::move(*NodeStore::open(dir.file("cells.hlod")));
    plain = std::move(*NodeStore::open(dir.file("plain.hlod")));
  }
};

const CellCity& cellCity() {
  static const CellCity city;  // its folder goes at exit
  return city;
}

// Whether (x, y) lies under a triangle of the mesh seen from above (z up).
bool coveredFromAbove(const LocalMesh& m, double x, double y) {
  for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {
    glm::dvec2 p[3];
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 w = m.centre + glm::dvec3(m.positions[m.indices[i + k]]);
      p[k] = {w.x - x, w.y - y};
    }
    const auto side = [](const glm::dvec2& a, const glm::dvec2& b) {
      return a.x * b.y - a.y * b.x;
    };
    const double s0 = side(p[0], p[1]), s1 = side(p[1], p[2]), s2 = side(p[2], p[0]);
    if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0)) {
      if (s0 != 0 || s1 != 0 || s2 != 0) return true;
    }
  }
  return false;
}

}  // namespace

TEST(CellNodes, AStoreWithCellsHasOneCellRootAboveEveryBlocksHlod0) {
  const Skeleton& s = cellCity().cells->skeleton();
  const Skeleton& plain = cellCity().plain->skeleton();
  ASSERT_EQ(s.roots.size(), 1u);
  EXPECT_TRUE(s.hasCells());
  EXPECT_FALSE(plain.hasCells());
  EXPECT_EQ(plain.roots.size(), 4u);
  // The same blocks below: the plain store's hlod_0 nodes, as many and as large.
  const std::vector<std::uint32_t> blocks = s.blockRoots();
  ASSERT_EQ(blocks.size(), 4u);
  std::uint64_t hlod0 = 0, plainHlod0 = 0;
  for (std::uint32_t r : blocks) {
    hlod0 += s.nodes[r].numTri;
    ASSERT_NE(s.nodes[r].parent, kNoNode);
    EXPECT_TRUE(s.nodes[s.nodes[r].parent].isCell());
  }
  for (std::uint32_t r : plain.roots) plainHlod0 += plain.nodes[r].numTri;
  EXPECT_EQ(hlod0, plainHlod0);
  for (std::uint32_t i = 0; i < s.nodes.size(); ++i) {
    const NodeInfo& n = s.nodes[i];
    if (!n.isCell()) continue;
    std::uint64_t below = 0;
    for (std::uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c) {
      below += s.nodes[c].numTri;
      EXPECT_GE(n.geometricError, s.nodes[c].geometricError);
      EXPECT_TRUE(glm::all(glm::lessThanEqual(n.bounds.min, s.nodes[c].bounds.min)) &&
                  glm::all(glm::lessThanEqual(s.nodes[c].bounds.max, n.bounds.max)));
    }
    EXPECT_GE(n.childCount, 2u);
    EXPECT_LT(n.numTri, below) << "cell " << i << " is no coarser than its children";
    EXPECT_EQ(n.minTri, 0u);  // drawn whole
    auto mesh = cellCity().cells->loadNode(i);
    ASSERT_TRUE(mesh.ok()) << mesh.message();
    // Its box holds what it draws (the underlay below the children's boxes too).
    for (const glm::vec3& q : mesh->positions) {
      const glm::dvec3 w = mesh->centre + glm::dvec3(q);
      EXPECT_TRUE(glm::all(glm::lessThanEqual(n.bounds.min - 1e-3, w)) &&
                  glm::all(glm::lessThanEqual(w, n.bounds.max + 1e-3)))
          << "cell " << i << " draws outside its box";
    }
    // Textured from its children (CellAtlas.h): coordinates into its atlas, a triangle's corners
    // at their places on its chart (not the one texel of a flat colour).
    ASSERT_TRUE(mesh->texture);
    ASSERT_EQ(mesh->texCoords.size(), mesh->positions.size());
    std::size_t spread = 0;
    for (const glm::vec2& t : mesh->texCoords)
      EXPECT_TRUE(t.x >= 0.0f && t.x <= 1.0f && t.y >= 0.0f && t.y <= 1.0f) << "cell " << i;
    for (std::size_t k = 0; k + 2 < mesh->indices.size(); k += 3)
      spread += mesh->texCoords[mesh->indices[k]] != mesh->texCoords[mesh->indices[k + 1]];
    EXPECT_GT(spread, mesh->indices.size() / 3 / 2) << "cell " << i;
  }
}

TEST(CellNodes, TheTopCellKeepsTheGroundUnderEveryStreetBetweenItsBlocks) {
  const NodeStore& store = *cellCity().cells;
  const Skeleton& s = store.skeleton();
  auto top = store.loadNode(s.roots[0]);
  ASSERT_TRUE(top.ok()) << top.message();
  // The blocks' ground reaches the middles of their streets: together they cover their box.
  const Aabb box = s.nodes[s.roots[0]].bounds;
  int missed = 0, samples = 0;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 60; ++j, ++samples) {
      const double x = box.min.x + (i + 0.5) / 60.0 * (box.max.x - box.min.x);
      const double y = box.min.y + (j + 0.5) / 60.0 * (box.max.y - box.min.y);
      missed += !coveredFromAbove(*top, x, y);
    }
  EXPECT_EQ(missed, 0) << "of " << samples << " points of the city seen from above";
}

TEST(CellNodes, MergedChildrenCarryTheirMeanColoursIntoAFlatColouredPalette) {
  // Child a: one triangle on the left (red) half of a red|blue texture; child b: untextured,
  // green base colour.
  LocalMesh a, b;
  a.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  a.normals.assign(3, glm::vec3(0, 0, 1));
  a.texCoords = {{0.05f, 0.1f}, {0.45f, 0.1f}, {0.05f, 0.9f}};
  a.indices = {0, 1, 2};
  a.baseColor = glm::vec4(1.0f);
  auto texture = std::make_shared<Image>();
  texture->width = 2;
  texture->height = 1;
  texture->pixels = {255, 0, 0, 255, 0, 0, 255, 255};
  a.texture = texture;
  b = a;
  b.centre = {5, 0, 0};
  b.texture = nullptr;
  b.texCoords.clear();
  b.baseColor = {0.0f, 1.0f, 0.0f, 1.0f};
  const LocalMesh children[] = {a, b};
  const ColouredMesh merged = mergeCellChildren(children);
  ASSERT_EQ(merged.mesh.positions.size(), 6u);
  EXPECT_EQ(merged.mesh.positions[3], glm::dvec3(5, 0, 0));
  ASSERT_EQ(merged.colours.size(), 2u);
  const auto colourAt = [&](std::size_t v) {
    return merged.colours[std::size_t(merged.mesh.texCoords[v].x)];
  };
  for (std::size_t v = 0; v < 3; ++v) {
    EXPECT_EQ(colourAt(v), glm::vec4(1, 0, 0, 1)) << v;
    EXPECT_EQ(colourAt(v + 3), glm::vec4(0, 1, 0, 1)) << v;
  }
  const Mesh flat = flatColoured(merged.mesh, merged.colours);
  ASSERT_EQ(flat.triangleCount(), 2u);
  ASSERT_TRUE(flat.texture);
  for (std::size_t t = 0; t < 2; ++t) {
    const glm::vec2 uv = flat.texCoords[flat.indices[3 * t]];
    const int x = int(uv.x * float(flat.texture->width)),
              y = int(uv.y * float(flat.texture->height));
    const std::uint8_t* p = &flat.texture->pixels[(std::size_t(y) * flat.texture->width + x) * 4];
    EXPECT_EQ(int(p[0]), t == 0 ? 255 : 0);
    EXPECT_EQ(int(p[1]), t == 0 ? 0 : 255);
    EXPECT_EQ(int(p[2]), 0);
  }
}

TEST(CellNodes, FlatColouredKeepsACornersNormalOnlyWhereItAgreesWithItsFace) {
  // One triangle in z = 0 (face normal +z), colour 0 at every corner. Corner 0's normal is 30
  // degrees off the face, corner 1's 60 degrees, corner 2 has the face's.
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const float r30 = float(M_PI / 6.0), r60 = float(M_PI / 3.0);
  m.normals = {{std::sin(r30), 0, std::cos(r30)}, {std::sin(r60), 0, std::cos(r60)}, {0, 0, 1}};
  m.texCoords.assign(3, glm::vec2(0.0f));
  m.indices = {0, 1, 2};
  const glm::vec4 colours[] = {{0.5f, 0.5f, 0.5f, 1.0f}};
  const Mesh flat = flatColoured(m, colours);  // flat: the face's normal everywhere
  ASSERT_EQ(flat.normals.size(), 3u);
  for (const glm::vec3& n : flat.normals) EXPECT_EQ(n, glm::vec3(0, 0, 1));
  const Mesh smooth = flatColoured(m, colours, std::cos(float(M_PI / 4.0)));  // within 45 degrees
  ASSERT_EQ(smooth.normals.size(), 3u);
  EXPECT_EQ(smooth.normals[0], m.normals[0]);
  EXPECT_EQ(smooth.normals[1], glm::vec3(0, 0, 1));
  EXPECT_EQ(smooth.normals[2], glm::vec3(0, 0, 1));
}

TEST(CellNodes, TheDecoderRefusesCellsWhereTheTreeCannotHaveThem) {
  const Skeleton good = cellCity().cells->skeleton();
  const StoreFacts facts = cellCity().cells->facts();
  ASSERT_TRUE(decodeSkeleton(encodeSkeleton(good, facts)).ok());
  const std::uint32_t block = good.blockRoots().front();
  const auto refused = [&](const Skeleton& s) {
    return !decodeSkeleton(encodeSkeleton(s, facts)).ok();
  };
  {
    Skeleton s = good;  // a cell with a level
    s.nodes[0].level = 1;
    EXPECT_TRUE(refused(s));
  }
  {
    Skeleton s = good;  // a block's node below a block's node, at level 0
    const std::uint32_t child = s.nodes[block].firstChild;
    ASSERT_GT(s.nodes[block].childCount, 0u);
    s.nodes[child].level = 0;
    EXPECT_TRUE(refused(s));
  }
  {
    Skeleton s = good;  // a cell below a block's node
    const std::uint32_t child = s.nodes[block].firstChild;
    s.nodes[child].block = kCellBlock;
    EXPECT_TRUE(refused(s));
  }
  {
    Skeleton s = good;  // an hlod_0 node below a cell with level 1
    s.nodes[block].level = 1;
    EXPECT_TRUE(refused(s));
  }
}

TEST(CellNodes, AFarCameraDrawsTheTopCellAndFullDetailDrawsNoCell) {
  const Skeleton& s = cellCity().cells->skeleton();
  const Aabb box = s.nodes[s.roots[0]].bounds;
  View far;
  far.camera.position = box.centre() + glm::dvec3(0.0, -2000.0, 2000.0);
  far.camera.target = box.centre();
  SelectorParams params;
  params.lakhia.c_targetTime = 0.001;  // nothing but the coarsest fits
  AllResident all;
  auto lakhia = makeSelector("lakhia", s, params);
  ASSERT_TRUE(lakhia.ok());
  const Selection coarse = (*lakhia)->select(far, all);
  EXPECT_EQ(coarse.front, std::vector<std::uint32_t>{s.roots[0]});
  EXPECT_EQ(coarse.cellsDrawn, 1u);
  auto full = makeSelector("full", s, params);
  ASSERT_TRUE(full.ok());
  const Selection leaves = (*full)->select(far, all);
  EXPECT_EQ(leaves.cellsDrawn, 0u);
  for (std::uint32_t n : leaves.front) EXPECT_TRUE(s.isLeaf(n));
}

namespace {

// Open-border edges (used by one triangle), by position.
std::size_t openEdges(const Mesh& m) {
  std::map<std::pair<std::tuple<double, double, double>, std::tuple<double, double, double>>, int>
      uses;
  for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3)
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 a = m.positions[m.indices[i + k]],
                       b = m.positions[m.indices[i + (k + 1) % 3]];
      auto p = std::make_tuple(a.x, a.y, a.z), q = std::make_tuple(b.x, b.y, b.z);
      ++uses[{std::min(p, q), std::max(p, q)}];
    }
  std::size_t n = 0;
  for (const auto& [edge, count] : uses) n += count == 1;
  return n;
}

}  // namespace

TEST(CellNodes, StitchingWeldsTwoGroundsThatMeetWithDifferentVerticesOnTheirSide) {
  // Left: one quad [-1,0] x [0,2]; right: two quads [0,1] x [0,1] and [0,1] x [1,2], so the
  // right ground has a vertex at (0,1) in the middle of the left's edge (a T-junction).
  Mesh m;
  m.positions = {{-1, 0, 0}, {0, 0, 0}, {0, 2, 0}, {-1, 2, 0},  // left
                 {0, 0, 0},  {1, 0, 0}, {1, 1, 0}, {0, 1, 0},  {1, 2, 0}, {0, 2, 0}};
  m.normals.assign(m.positions.size(), glm::vec3(0, 0, 1));
  m.texCoords.assign(m.positions.size(), glm::vec2(0));
  m.indices = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 7, 6, 8, 7, 8, 9};
  const std::size_t before = openEdges(m);
  const double area = surfaceArea(m);
  const CutPlane side{0, 0.0};
  stitchBorders(m, std::span(&side, 1), UpAxis::Z, 1e-9);
  // The left quad's edge x = 0 is split at (0, 1): the two edges of the seam are used twice.
  EXPECT_EQ(openEdges(m), before - 3);
  EXPECT_EQ(m.triangleCount(), 7u);
  EXPECT_DOUBLE_EQ(surfaceArea(m), area);
  EXPECT_EQ(m.positions.size(), m.normals.size());
  EXPECT_EQ(m.positions.size(), m.texCoords.size());
}

TEST(CellNodes, OnlyTheSidesNoOtherBlockOfTheCellLiesAcrossAreOuter) {
  // Two blocks side by side along x, sharing the street middle x = 10.
  Aabb a, b;
  a.extend(glm::dvec3(0, 0, 0));
  a.extend(glm::dvec3(10, 10, 5));
  b.extend(glm::dvec3(10, 0, 0));
  b.extend(glm::dvec3(20, 10, 5));
  const std::vector<std::vector<CutPlane>> sides = {{{0, 0.0}, {0, 10.0}, {1, 0.0}, {1, 10.0}},
                                                    {{0, 10.0}, {0, 20.0}, {1, 0.0}, {1, 10.0}}};
  const Aabb boxes[] = {a, b};
  const std::vector<CutPlane> outer = outerSides(boxes, sides, UpAxis::Z);
  const auto has = [&](int axis, double value) {
    return std::any_of(outer.begin(), outer.end(),
                       [&](const CutPlane& c) { return c.axis == axis && c.value == value; });
  };
  EXPECT_EQ(outer.size(), 4u);
  EXPECT_FALSE(has(0, 10.0));
  EXPECT_TRUE(has(0, 0.0) && has(0, 20.0) && has(1, 0.0) && has(1, 10.0));
}

TEST(CellNodes, TheUnderlayLiesBelowTheGroundFacingUpInTheGroundsColour) {
  // Ground (grey, up) at z = 0 and a roof (red, up) at z = 10 over a 100 x 50 box.
  Mesh input;
  input.positions = {{0, 0, 0}, {100, 0, 0}, {100, 50, 0}, {0, 0, 10}, {10, 0, 10}, {10, 10, 10}};
  input.texCoords = {{0, 0}, {0, 0}, {0, 0}, {1, 0}, {1, 0}, {1, 0}};
  input.indices = {0, 1, 2, 3, 4, 5};
  std::vector<glm::vec4> colours = {{0.5f, 0.5f, 0.5f, 1.0f}, {1.0f, 0.0f, 0.0f, 1.0f}};
  Aabb box;
  box.extend(glm::dvec3(0, 0, 0));
  box.extend(glm::dvec3(100, 50, 10));
  Mesh mesh;
  addUnderlay(mesh, input, colours, box, UpAxis::Z);
  ASSERT_EQ(mesh.triangleCount(), 2u);
  ASSERT_EQ(colours.size(), 3u);
  EXPECT_EQ(colours[2], glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));  // the ground's, not the roof's
  for (std::size_t t = 0; t < 2; ++t) {
    const glm::dvec3 p = mesh.positions[mesh.indices[3 * t]],
                     q = mesh.positions[mesh.indices[3 * t + 1]],
                     r = mesh.positions[mesh.indices[3 * t + 2]];
    EXPECT_GT(glm::cross(q - p, r - p).z, 0.0);  // facing up
    EXPECT_DOUBLE_EQ(p.z, -kUnderlayDepth * 100.0);
  }
  EXPECT_DOUBLE_EQ(surfaceArea(mesh), 100.0 * 50.0);
}

namespace {

// A box's roof and walls as one welded part, in colour `roof` (index) and `wall`.
void addBoxPart(Mesh& m, glm::dvec3 lo, glm::dvec3 hi, float roof, float wall) {
  BuildingBox b;
  b.lo = {lo.x, lo.y};
  b.hi = {hi.x, hi.y};
  b.bottom = lo.z;
  b.top = hi.z;
  std::vector<glm::vec4> scratch;
  Mesh part;
  appendBox(part, b, scratch, UpAxis::Z);
  // appendBox gives each face its own vertices: weld by position into one part.
  for (auto& t : part.texCoords) t.x = t.x == 0.0f ? wall : roof;
  const auto base = std::uint32_t(m.positions.size());
  m.positions.insert(m.positions.end(), part.positions.begin(), part.positions.end());
  m.normals.insert(m.normals.end(), part.normals.begin(), part.normals.end());
  m.texCoords.insert(m.texCoords.end(), part.texCoords.begin(), part.texCoords.end());
  for (std::uint32_t i : part.indices) m.indices.push_back(base + i);
}

// Ground: 100 x 100 at z = 0, colour 0.
Mesh groundSquare() {
  Mesh m;
  m.positions = {{0, 0, 0}, {100, 0, 0}, {100, 100, 0}, {0, 100, 0}};
  m.normals.assign(4, glm::vec3(0, 0, 1));
  m.texCoords.assign(4, glm::vec2(0));
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

}  // namespace

TEST(CellNodes, BuildingsBecomeBoxesAndTheGroundAndACourtyardRingStay) {
  const std::vector<glm::vec4> colours = {
      {0.5f, 0.5f, 0.5f, 1.0f}, {1.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f, 1.0f}};
  Mesh m = groundSquare();
  // A tower 10 x 20 x 30 (red roof, blue walls).
  addBoxPart(m, {10, 10, 0}, {20, 30, 30}, 1.0f, 2.0f);
  // A low wide shed 40 x 40 x 5, and a kerb 60 m long, 0.3 m wide, 0.2 m high: ground.
  addBoxPart(m, {50, 50, 0}, {90, 90, 5}, 1.0f, 2.0f);
  addBoxPart(m, {0, 95, 0}, {60, 95.3, 0.2}, 1.0f, 2.0f);
  const std::vector<BuildingBox> boxes = takeBuildings(m, colours, UpAxis::Z);
  // The shed is 8 times as wide as tall: ground, as the kerb; the tower is a box.
  ASSERT_EQ(boxes.size(), 1u);
  // The tallest and widest first: the tower, axis-aligned (its edges' main direction).
  const BuildingBox& tower = boxes.front();
  EXPECT_NEAR(std::abs(tower.axis.x) + std::abs(tower.axis.y), 1.0, 1e-9);
  EXPECT_NEAR(tower.top - tower.bottom, 30.0, 1e-9);
  EXPECT_NEAR((tower.hi.x - tower.lo.x) * (tower.hi.y - tower.lo.y), 200.0, 1e-6);
  EXPECT_EQ(tower.roof, colours[1]);
  EXPECT_EQ(tower.side, colours[2]);
  EXPECT_EQ(m.triangleCount(), 2u + 10u + 10u);  // the ground, the shed and the kerb stay
}

TEST(CellNodes, PartsJoinedRoundACourtyardAreNoBox) {
  const std::vector<glm::vec4> colours = {{1, 1, 1, 1}, {1, 0, 0, 1}, {0, 0, 1, 1}};
  // Four slabs 20 m high (tall enough for a building), 2 m wide, round a courtyard: their roofs
  // cover 384 of their box's 2,500 m2.
  Mesh m;
  addBoxPart(m, {0, 0, 0}, {50, 2, 20}, 1.0f, 2.0f);
  addBoxPart(m, {0, 48, 0}, {50, 50, 20}, 1.0f, 2.0f);
  addBoxPart(m, {0, 2, 0}, {2, 48, 20}, 1.0f, 2.0f);
  addBoxPart(m, {48, 2, 0}, {50, 48, 20}, 1.0f, 2.0f);
  // The side slabs start where the long ones end: they share corner positions, one part.
  const std::size_t before = m.triangleCount();
  Mesh kept = m;
  EXPECT_TRUE(takeBuildings(kept, colours, UpAxis::Z).empty());
  EXPECT_EQ(kept.triangleCount(), before);
  // Asked for them, it hands them over: simplified apart from the ground.
  std::vector<std::uint32_t> others;
  EXPECT_TRUE(takeBuildings(m, colours, UpAxis::Z, &others).empty());
  EXPECT_EQ(m.triangleCount(), 0u);
  EXPECT_EQ(others.size(), 3 * before);
}

TEST(CellNodes, ARoofThatSharesNoPositionWithItsWallsIsTakenIntoItsBuilding) {
  const std::vector<glm::vec4> colours = {
      {0.5f, 0.5f, 0.5f, 1.0f}, {1.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f, 1.0f}};
  Mesh m = groundSquare();  // under the tower too
  // A tower's walls 10 x 20 x 30 without their roof (appendBox's first quad), as a simplified
  // block leaves them when the cornice between walls and roof is gone.
  addBoxPart(m, {10, 10, 0}, {20, 30, 30}, 1.0f, 2.0f);
  m.indices.erase(m.indices.begin() + 6, m.indices.begin() + 12);
  // Its roof, 0.5 m inside the walls, sharing no position with them, and a unit on the roof.
  const auto base = std::uint32_t(m.positions.size());
  for (const glm::dvec3& p : {glm::dvec3(10.5, 10.5, 30), glm::dvec3(19.5, 10.5, 30),
                              glm::dvec3(19.5, 29.5, 30), glm::dvec3(10.5, 29.5, 30)}) {
    m.positions.push_back(p);
    m.normals.emplace_back(0, 0, 1);
    m.texCoords.emplace_back(1.0f, 0.0f);
  }
  m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  addBoxPart(m, {14, 18, 30}, {16, 20, 32}, 1.0f, 2.0f);
  const std::vector<BuildingBox> boxes = takeBuildings(m, colours, UpAxis::Z);
  // One box: walls, roof and unit. Alone, the roof would be ground and the walls no box.
  ASSERT_EQ(boxes.size(), 1u);
  const BuildingBox& tower = boxes.front();
  EXPECT_NEAR(tower.bottom, 0.0, 1e-9);
  EXPECT_GT(tower.top, 30.0);
  EXPECT_LT(tower.top, 30.2);  // the roof's height, the unit's 4 m2 of 175 at 32 m in the mean
  EXPECT_NEAR((tower.hi.x - tower.lo.x) * (tower.hi.y - tower.lo.y), 200.0, 1e-6);
  EXPECT_EQ(tower.roof, colours[1]);
  EXPECT_EQ(m.triangleCount(), 2u);  // the ground stays: it lies under the tower, not on it
}
