// A region of several inputs is one store: a city folder and two geo-referenced models land in
// the first input's east-north-up frame through ECEF, each block anchored where it is on the
// earth, all in one quadtree; an input without an anchor cannot join them.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

#include "hlod/builder/HlodBuilder.h"
#include "hlod/city/City.h"
#include "hlod/store/NodeStore.h"

using namespace hlod;
namespace fs = std::filesystem;

namespace {

// A model of `n` 10 m boxes (city objects) 30 m apart along x, in the ENU frame at `origin`.
Model boxes(const LatLon& origin, int n) {
  Model m;
  m.zUp = true;
  m.crs.toEnu = true;
  m.crs.epsg = 4979;
  m.crs.originLat = origin.lat;
  m.crs.originLon = origin.lon;
  m.meshes.resize(1);
  for (int b = 0; b < n; ++b) {
    Mesh& mesh = m.meshes[0];
    const auto base = std::uint32_t(mesh.positions.size());
    const auto first = std::uint32_t(mesh.triangleCount());
    for (int k = 0; k < 8; ++k)
      mesh.positions.push_back(
          {30.0 * b + (k & 1 ? 10.0 : 0.0), k & 2 ? 10.0 : 0.0, k & 4 ? 10.0 : 0.0});
    for (std::uint32_t i : {0u, 2u, 1u, 1u, 2u, 3u, 4u, 5u, 6u, 5u, 7u, 6u, 0u, 1u, 4u, 1u, 5u, 4u,
                            2u, 6u, 3u, 3u, 6u, 7u, 0u, 4u, 2u, 2u, 4u, 6u, 1u, 3u, 5u, 3u, 7u, 5u})
      mesh.indices.push_back(base + i);
    m.objectRuns.push_back({std::uint32_t(b), 0, first, 12});
  }
  m.cityObjects = std::size_t(n);
  return m;
}

struct TempStore {
  fs::path dir = fs::temp_directory_path() / ("hlodr-region-" + std::to_string(::getpid()));
  ~TempStore() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

}  // namespace

TEST(RegionBuild, ACityAndTwoModelsShareOneFrameAndOneQuadtree) {
  TempStore tmp;
  CityOptions city;
  city.blocks = 1;
  city.textureSize = 64;
  ASSERT_TRUE(writeCity(tmp.dir / "city", city).ok());
  const LatLon near{kCityOriginLat + 0.01, kCityOriginLon + 0.01, 0.0};  // ~1.4 km away
  const LatLon far{51.91, 4.45, 0.0};                                    // Rotterdam
  std::vector<BuildInput> inputs(3);
  inputs[0].name = "city";
  inputs[0].cityDir = tmp.dir / "city";
  inputs[1].name = "near";
  inputs[1].model = boxes(near, 3);
  inputs[2].name = "far";
  inputs[2].model = boxes(far, 2);
  BuildOptions options;
  options.threads = 2;
  options.blockSize = 25.0;  // one box per block
  auto built = buildStoreFromInputs(std::move(inputs), tmp.dir / "region.hlod", options);
  ASSERT_TRUE(built.ok()) << built.message();
  auto store = NodeStore::open(tmp.dir / "region.hlod");
  ASSERT_TRUE(store.ok()) << store.message();
  const Skeleton& s = (*store)->skeleton();
  EXPECT_TRUE(s.crs.toEnu);
  EXPECT_EQ(s.crs.originLat, kCityOriginLat);
  EXPECT_EQ(s.crs.originLon, kCityOriginLon);
  ASSERT_EQ(s.quadtree.domain, QuadtreeDomain::Geographic);
  EXPECT_EQ(s.quadtree.blocks.size(), s.roots.size());
  EXPECT_EQ(quadtreeStats(s.quadtree).blocks, 1u + 3u + 2u);
  // Each model block lies in the store's frame where its anchor is on the earth.
  const EnuFrame frame(LatLon{kCityOriginLat, kCityOriginLon, 0.0});
  std::size_t nearBlocks = 0, farBlocks = 0;
  for (const QuadBlock& b : s.quadtree.blocks) {
    const LatLon at{b.anchor.y, b.anchor.x, 0.0};
    const bool isNear = std::abs(at.lat - near.lat) < 0.001;
    const bool isFar = std::abs(at.lat - far.lat) < 0.001;
    nearBlocks += isNear;
    farBlocks += isFar;
    if (!isNear && !isFar) continue;
    const glm::dvec3 expected = frame.fromGeodetic(at);
    const glm::dvec3 centre = s.nodes[b.root].bounds.centre();
    // The anchor is the box's centre on the ground; the box's centre is 5 m up it (along the
    // box's own up, which far away is not the store's z).
    EXPECT_LT(glm::length(centre - expected), 6.0) << at.lat << " " << at.lon;
  }
  EXPECT_EQ(nearBlocks, 3u);
  EXPECT_EQ(farBlocks, 2u);
}

TEST(RegionBuild, AnInputWithoutAGeographicAnchorCannotJoinARegion) {
  TempStore tmp;
  std::vector<BuildInput> inputs(2);
  inputs[0].name = "near.city.json";
  inputs[0].model = boxes({52.0, 5.0, 0.0}, 2);
  inputs[1].name = "bunny.off";
  inputs[1].model = boxes({52.0, 5.0, 0.0}, 1);
  inputs[1].model.crs = {};
  auto built = buildStoreFromInputs(std::move(inputs), tmp.dir / "x.hlod", BuildOptions{});
  ASSERT_FALSE(built.ok());
  EXPECT_NE(built.message().find("bunny.off has no geographic anchor"), std::string::npos)
      << built.message();
  EXPECT_FALSE(fs::exists(tmp.dir / "x.hlod"));
}
