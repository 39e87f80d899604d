// Geographic anchors of city blocks (lat/lon/height) placed in the city's east-north-up frame in
// double precision (hlod/geodesy/Geodesy.h, readCityManifest, loadCityBlock). The cases where a
// local tangent plane built from differences of longitude goes wrong: a city straddling the
// antimeridian (a difference of 359.999 degrees is 0.001) and one around a pole (where east
// and north turn with the meridian, and a longitude difference of 180 degrees is a few metres).
#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "HardcaseFolder.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/city/City.h"
#include "hlod/export/PlyWriter.h"

namespace {

using hlod::LatLon;
using nlohmann::json;

constexpr double kRadPerDeg = 0.017453292519943295;

// A 10 x 6 x 20 m box, x in [-5, 5], y in [-3, 3], z in [0, 20], in its anchor's ENU frame.
hlod::Mesh tower() {
  hlod::Mesh m;
  for (int k = 0; k < 8; ++k)
    m.positions.push_back({k & 1 ? 5.0 : -5.0, k & 2 ? 3.0 : -3.0, k & 4 ? 20.0 : 0.0});
  m.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
               2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  return m;
}

json anchor(const LatLon& p) {
  return {{"lat", p.lat}, {"lon", p.lon}, {"height", p.height}};
}

class GeographicAnchors : public hardcase::Folder {
 protected:
  // A city folder with one tower per anchor, each in the ENU frame of its anchor.
  void writeCity(const LatLon& origin, const std::vector<LatLon>& anchors) {
    json blocks = json::array();
    for (std::size_t i = 0; i < anchors.size(); ++i) {
      const std::string name = "tower" + std::to_string(i);
      ASSERT_TRUE(hlod::writePly(dir / (name + ".ply"), tower()).ok());
      blocks.push_back({{"name", name},
                        {"mesh", name + ".ply"},
                        {"triangles", 12},
                        {"bounds", {{-5, -3, 0}, {5, 3, 20}}},
                        {"frame", "anchor"},
                        {"anchor", anchor(anchors[i])}});
    }
    const json manifest = {
        {"format", "hlodr-city"}, {"version", 1}, {"origin", anchor(origin)}, {"blocks", blocks}};
    write("city.json", manifest.dump());
  }
  // Block i in city coordinates.
  hlod::Mesh block(std::size_t i) {
    auto m = hlod::readCityManifest(dir);
    EXPECT_TRUE(m.ok()) << m.message();
    if (!m) return {};
    auto b = hlod::loadCityBlock(*m, i);
    EXPECT_TRUE(b.ok()) << b.message();
    return b ? std::move(*b) : hlod::Mesh{};
  }
};

// The tower is moved rigidly: every edge keeps its length to a micrometre.
void expectRigid(const hlod::Mesh& moved) {
  const hlod::Mesh local = tower();
  ASSERT_EQ(moved.positions.size(), local.positions.size());
  for (std::size_t a = 0; a < local.positions.size(); ++a)
    for (std::size_t b = a + 1; b < local.positions.size(); ++b)
      EXPECT_NEAR(glm::length(moved.positions[a] - moved.positions[b]),
                  glm::length(local.positions[a] - local.positions[b]), 1e-6);
}

// The prime vertical radius N at a latitude (WGS84), for closed-form expectations.
double primeVertical(double latDeg) {
  const double s = std::sin(latDeg * kRadPerDeg);
  return hlod::kWgs84A / std::sqrt(1.0 - hlod::kWgs84E2 * s * s);
}

TEST_F(GeographicAnchors, ACityAcrossTheAntimeridianKeepsItsBlocksMetresApart) {
  // Origin 0.0005 degrees west of the antimeridian; one tower 0.001 degrees east of it, across
  // the line (lon -179.9995), one 0.0005 degrees west (lon 179.999).
  const double lat = -17.7;  // Fiji
  const LatLon origin{lat, 179.9995, 0.0};
  writeCity(origin, {{lat, -179.9995, 0.0}, {lat, 179.999, 0.0}});
  // On one parallel, the east offset of a point dlon away is exactly N cos(lat) sin(dlon) (the
  // chord's east component); the small rest is north and down, from the earth's curvature.
  const double r = primeVertical(lat) * std::cos(lat * kRadPerDeg);
  const double expectEast[] = {r * std::sin(0.001 * kRadPerDeg),
                               -r * std::sin(0.0005 * kRadPerDeg)};
  for (std::size_t i = 0; i < 2; ++i) {
    const hlod::Mesh m = block(i);
    ASSERT_EQ(m.positions.size(), 8u);
    const glm::dvec3 base = (m.positions[0] + m.positions[3]) * 0.5;  // the foot's centre
    EXPECT_NEAR(base.x, expectEast[i], 1e-3) << "tower " << i;        // ~106 m and ~-53 m
    EXPECT_LT(std::abs(base.y), 0.01) << "tower " << i;
    EXPECT_LT(std::abs(base.z), 0.01) << "tower " << i;  // a 106 m chord sags 0.9 mm
    // Upright and facing as its anchor's frame: local east stays east across the line.
    const glm::dvec3 upAxis = glm::normalize(m.positions[4] - m.positions[0]);
    const glm::dvec3 eastAxis = glm::normalize(m.positions[1] - m.positions[0]);
    EXPECT_GT(upAxis.z, 1.0 - 1e-9);
    EXPECT_GT(eastAxis.x, 1.0 - 1e-9);
    expectRigid(m);
  }
  // The manifest's bounds are moved with the blocks: the city is 160 m wide, not 40,000 km.
  auto manifest = hlod::readCityManifest(dir);
  ASSERT_TRUE(manifest.ok()) << manifest.message();
  hlod::Aabb all;
  for (const auto& b : manifest->blocks) all.extend(b.bounds);
  EXPECT_LT(all.size().x, 200.0);
  EXPECT_NEAR(manifest->blocks[0].bounds.centre().x, expectEast[0], 0.01);
}

TEST_F(GeographicAnchors, ACityAroundThePoleKeepsItsBlocksWhereTheyAre) {
  // Origin 11 m from the north pole on the prime meridian; one tower on the far side of the pole
  // (lon 180, as far from it), one at the pole itself, one a quarter turn round (lon 90).
  const double lat = 89.9999;
  const LatLon origin{lat, 0.0, 0.0};
  writeCity(origin, {{lat, 180.0, 0.0}, {90.0, 0.0, 0.0}, {lat, 90.0, 0.0}});
  // In ECEF the origin is (N cos(lat), 0, z) and the far tower (-N cos(lat), 0, z): 2 N cos(lat)
  // apart along -x, which at the origin is north (sin(lat)) and down (cos(lat)).
  const double nc = primeVertical(lat) * std::cos(lat * kRadPerDeg);  // 11.17 m
  const glm::dvec3 expectFoot[] = {
      {0.0, 2.0 * nc * std::sin(lat * kRadPerDeg), -2.0 * nc * std::cos(lat * kRadPerDeg)},
      {0.0, nc * std::sin(lat * kRadPerDeg), 0.0},  // the pole: straight on, about 11.17 m
      {nc, nc * std::sin(lat * kRadPerDeg), 0.0},   // lon 90: as far east as the pole is north
  };
  for (std::size_t i = 0; i < 3; ++i) {
    const hlod::Mesh m = block(i);
    ASSERT_EQ(m.positions.size(), 8u);
    const glm::dvec3 foot = (m.positions[0] + m.positions[3]) * 0.5;
    EXPECT_NEAR(foot.x, expectFoot[i].x, 1e-3) << "tower " << i;
    EXPECT_NEAR(foot.y, expectFoot[i].y, 1e-3) << "tower " << i;
    EXPECT_NEAR(foot.z, expectFoot[i].z, 1e-3) << "tower " << i;
    EXPECT_GT(glm::normalize(m.positions[4] - m.positions[0]).z, 1.0 - 1e-9) << "tower " << i;
    expectRigid(m);
  }
  // Beyond the pole north is south: the far tower's own north axis points back at the origin.
  const hlod::Mesh far = block(0);
  const glm::dvec3 northAxis = glm::normalize(far.positions[2] - far.positions[0]);
  EXPECT_LT(northAxis.y, -1.0 + 1e-9);
  // And at lon 90 the tower's north points west, towards the pole's side of the origin.
  const hlod::Mesh quarter = block(2);
  EXPECT_LT(glm::normalize(quarter.positions[2] - quarter.positions[0]).x, -1.0 + 1e-6);
}

TEST_F(GeographicAnchors, ABuiltStoreOfAnAntimeridianCityHoldsItsBlocksInTheCitysFrame) {
  const LatLon origin{-17.7, 179.9995, 10.0};
  writeCity(origin, {{-17.7, -179.9995, 10.0}, {-17.7005, 179.9995, 10.0}});
  hlod::BuildOptions options;
  const auto store = dir / "city.hlod";
  auto sk = hlod::buildStoreFromCity(dir, store, options);
  ASSERT_TRUE(sk.ok()) << sk.message();
  ASSERT_EQ(sk->roots.size(), 2u);
  // 106 m east, and 55 m south: the roots' boxes are the towers', in metres of the city.
  const glm::dvec3 c0 = sk->nodes[sk->roots[0]].bounds.centre();
  const glm::dvec3 c1 = sk->nodes[sk->roots[1]].bounds.centre();
  EXPECT_NEAR(c0.x, 106.1, 0.5);
  EXPECT_NEAR(c0.y, 0.0, 0.05);
  EXPECT_NEAR(c1.x, 0.0, 0.05);
  EXPECT_NEAR(c1.y, -55.3, 0.5);
  for (const auto& n : sk->nodes) {
    EXPECT_NEAR(n.bounds.size().z, 20.0, 1e-3);
    EXPECT_LT(glm::length(n.bounds.centre()), 200.0);
  }
}

TEST_F(GeographicAnchors, BlocksWithoutAnAnchorAreAnchoredInTheManifestsOwnFrame) {
  // A city-frame block 106 m east of an origin by the antimeridian: its derived anchor is across
  // the line (longitude -179.9995, wrapped), not 180.0005 and not near the default city.
  ASSERT_TRUE(hlod::writePly(dir / "b.ply", tower()).ok());
  const double r = primeVertical(-17.7) * std::cos(-17.7 * kRadPerDeg);
  const double east = r * std::sin(0.001 * kRadPerDeg);
  const json manifest = {{"format", "hlodr-city"},
                         {"version", 1},
                         {"origin", {{"lat", -17.7}, {"lon", 179.9995}}},
                         {"blocks",
                          {{{"name", "b"},
                            {"mesh", "b.ply"},
                            {"triangles", 12},
                            {"bounds", {{east - 5, -3, 0}, {east + 5, 3, 0}}}}}}};
  write("city.json", manifest.dump());
  auto m = hlod::readCityManifest(dir);
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_NEAR(m->blocks[0].anchor.lon, -179.9995, 1e-9);
  EXPECT_NEAR(m->blocks[0].anchor.lat, -17.7, 1e-6);
}

TEST_F(GeographicAnchors, AnAnchorFrameWithoutAnAnchorOrAnUnknownFrameIsAClearError) {
  ASSERT_TRUE(hlod::writePly(dir / "b.ply", tower()).ok());
  json block = {{"name", "b"},
                {"mesh", "b.ply"},
                {"triangles", 12},
                {"bounds", {{-5, -3, 0}, {5, 3, 20}}},
                {"frame", "anchor"}};
  auto manifest = [&](const json& b) {
    return json{{"format", "hlodr-city"}, {"version", 1}, {"blocks", {b}}}.dump();
  };
  write("city.json", manifest(block));
  auto m = hlod::readCityManifest(dir);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.message().find("no anchor"), std::string::npos) << m.message();
  block["frame"] = "ecef";
  write("city.json", manifest(block));
  m = hlod::readCityManifest(dir);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.message().find("frame"), std::string::npos) << m.message();
  block["frame"] = "anchor";
  block["anchor"] = {{"lat", 10}, {"lon", 20}, {"height", 1e300}};
  write("city.json", manifest(block));
  m = hlod::readCityManifest(dir);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.message().find("height"), std::string::npos) << m.message();
}

}  // namespace
