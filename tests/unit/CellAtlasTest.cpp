// A cell's atlas baked from its children (builder/CellAtlas.h), on a hand-made cell: two
// textured boxes as the children, and the cell's own boxes standing a little outside them.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "builder/CellAtlas.h"

namespace hlod {
namespace {

using Rgba = std::array<std::uint8_t, 4>;

// A box's roof and four walls (no floor), counter-clockwise seen from outside, three vertices per
// triangle; each vertex gets `roofUv` on the roof and `wallUv` on the walls.
Mesh boxMesh(const glm::dvec3& lo, const glm::dvec3& hi, glm::vec2 roofUv = {},
             glm::vec2 wallUv = {}) {
  Mesh m;
  const auto quad = [&](glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 d, glm::vec2 uv) {
    for (const glm::dvec3& p : {a, b, c, a, c, d}) {
      m.indices.push_back(std::uint32_t(m.positions.size()));
      m.positions.push_back(p);
      m.texCoords.push_back(uv);
    }
  };
  const glm::dvec3 c[4] = {{lo.x, lo.y, 0}, {hi.x, lo.y, 0}, {hi.x, hi.y, 0}, {lo.x, hi.y, 0}};
  const glm::dvec3 top(0, 0, hi.z), bottom(0, 0, lo.z);
  quad(c[0] + top, c[1] + top, c[2] + top, c[3] + top, roofUv);
  for (int k = 0; k < 4; ++k)
    quad(c[k] + bottom, c[(k + 1) % 4] + bottom, c[(k + 1) % 4] + top, c[k] + top, wallUv);
  return m;
}

// A child: the box with a 2 x 1 texture, the roof's colour at the left texel, the walls' at the
// right one (sampled at their centres, so bilinear filtering gives them exactly).
LocalMesh texturedBox(const glm::dvec3& lo, const glm::dvec3& hi, Rgba roof, Rgba wall) {
  const Mesh m = boxMesh(lo, hi, {0.25f, 0.5f}, {0.75f, 0.5f});
  LocalMesh out;
  out.centre = (lo + hi) * 0.5;
  for (const glm::dvec3& p : m.positions) out.positions.push_back(glm::vec3(p - out.centre));
  out.normals.assign(m.positions.size(), glm::vec3(0, 0, 1));
  out.texCoords = m.texCoords;
  out.indices = m.indices;
  out.baseColor = glm::vec4(1.0f);
  out.oneSided = true;
  auto image = std::make_shared<Image>();
  image->width = 2;
  image->height = 1;
  image->pixels = {roof[0], roof[1], roof[2], roof[3], wall[0], wall[1], wall[2], wall[3]};
  out.texture = std::move(image);
  return out;
}

Rgba texelAt(const Image& img, glm::vec2 uv) {
  const int x = std::clamp(int(uv.x * img.width), 0, img.width - 1);
  const int y = std::clamp(int(uv.y * img.height), 0, img.height - 1);
  const std::uint8_t* p = &img.pixels[(std::size_t(y) * img.width + x) * 4];
  return {p[0], p[1], p[2], p[3]};
}

TEST(CellAtlas, TexelsTakeTheChildrensColoursSeenFromAboveAndFromTheSide) {
  const Rgba red{200, 30, 30, 255}, blue{30, 30, 200, 255};
  const Rgba green{30, 180, 30, 255}, yellow{220, 210, 40, 255};
  const LocalMesh children[2] = {texturedBox({0, 0, 0}, {10, 10, 20}, red, blue),
                                 texturedBox({20, 0, 0}, {30, 10, 8}, green, yellow)};
  // The cell: each box half a metre larger than the child it stands for, one mesh.
  Mesh cell = boxMesh({-0.5, -0.5, 0}, {10.5, 10.5, 20.5});
  const Mesh second = boxMesh({19.5, -0.5, 0}, {30.5, 10.5, 8.5});
  const auto base = std::uint32_t(cell.positions.size());
  cell.positions.insert(cell.positions.end(), second.positions.begin(), second.positions.end());
  for (std::uint32_t i : second.indices) cell.indices.push_back(base + i);
  cell.texCoords.clear();

  CellAtlasOptions o;
  o.texelSize = 0.5;
  o.castDepth = 2.0;
  const CellAtlasStats stats = bakeCellAtlas(cell, children, o);
  ASSERT_TRUE(cell.texture);
  ASSERT_EQ(cell.texCoords.size(), cell.positions.size());
  // The plan, and four walls per box.
  EXPECT_EQ(stats.charts, 9u);
  // The cell's walls reach half a metre past the children's at their sides and top: casts there
  // meet nothing (a texel's band around each wall: 13% of the texels), and take the nearest
  // face's colour.
  EXPECT_GT(stats.missed, 0u);
  EXPECT_LT(stats.missed, stats.texels / 5);
  EXPECT_GT(stats.texels, 0u);
  EXPECT_LE(std::max(cell.texture->width, cell.texture->height), o.maxSide);

  // Inside each triangle (its centroid and points towards its corners), the colour of what it
  // stands for: the roofs' from above, the walls' from the side.
  for (std::uint32_t t = 0; t * 3 < cell.indices.size(); ++t) {
    const std::uint32_t* v = &cell.indices[3 * t];
    const bool first = t < base / 3;
    const bool roof = (t % 10) < 2;  // each box: its roof's two triangles, then its walls'
    const Rgba want = first ? (roof ? red : blue) : (roof ? green : yellow);
    for (const glm::dvec3 w : {glm::dvec3(1.0 / 3), glm::dvec3(0.6, 0.2, 0.2),
                               glm::dvec3(0.2, 0.6, 0.2), glm::dvec3(0.2, 0.2, 0.6)}) {
      const glm::vec2 uv = float(w.x) * cell.texCoords[v[0]] + float(w.y) * cell.texCoords[v[1]] +
                           float(w.z) * cell.texCoords[v[2]];
      EXPECT_EQ(texelAt(*cell.texture, uv), want) << "triangle " << t;
    }
  }
}

TEST(CellAtlas, AnAtlasTooLargeForItsSideGetsLargerTexels) {
  const LocalMesh child = texturedBox({0, 0, 0}, {100, 100, 10}, {1, 2, 3, 255}, {4, 5, 6, 255});
  Mesh cell = boxMesh({0, 0, 0}, {100, 100, 10});
  cell.texCoords.clear();
  CellAtlasOptions o;
  o.texelSize = 0.01;  // 10,000 texels across the roof
  o.maxSide = 256;
  o.castDepth = 1.0;
  const CellAtlasStats stats = bakeCellAtlas(cell, {&child, 1}, o);
  ASSERT_TRUE(cell.texture);
  EXPECT_LE(cell.texture->width, 256);
  EXPECT_LE(cell.texture->height, 256);
  EXPECT_GT(stats.texelSize, 0.01 * 40);
  EXPECT_EQ(texelAt(*cell.texture, cell.texCoords[0] * 0.5f + cell.texCoords[2] * 0.5f),
            (Rgba{1, 2, 3, 255}));
}

TEST(CellAtlas, TheChildrensTexelIsTheirTexturedAreaOverTheirTexels) {
  // A 10 x 10 x 20 box: roof 100 m2, walls 800 m2, on a 2 x 1 texture: 450 m2 a texel.
  const LocalMesh box = texturedBox({0, 0, 0}, {10, 10, 20}, {}, {});
  EXPECT_NEAR(texelSizeOf({&box, 1}), std::sqrt(450.0), 1e-9);
  LocalMesh plain = box;
  plain.texture = nullptr;
  EXPECT_EQ(texelSizeOf({&plain, 1}), 0.0);
  const LocalMesh both[2] = {box, plain};
  EXPECT_NEAR(texelSizeOf(both), std::sqrt(450.0), 1e-9);
}

}  // namespace
}  // namespace hlod
