// The procedural city (hlod/city/City.h): determinism, size, layout, attributes, and the city
// folder.
#include "hlod/city/City.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

namespace {

namespace fs = std::filesystem;
using hlod::CityOptions;
using hlod::Mesh;

// A fresh, empty temporary folder per test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("hlodr_city_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeFile(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

CityOptions geometryOnly(std::uint64_t seed = hlod::kDefaultCitySeed) {
  CityOptions o;
  o.seed = seed;
  o.textures = false;
  return o;
}

// Bounds and triangle counts of the default city's blocks, generated once for several tests.
struct BlockSummary {
  hlod::Aabb bounds;
  std::size_t triangles = 0;
};
const std::vector<BlockSummary>& defaultCityBlocks() {
  static const std::vector<BlockSummary> blocks = [] {
    std::vector<BlockSummary> out;
    for (int i = 0; i < hlod::kDefaultCityBlocks; ++i) {
      const Mesh m = hlod::generateBlock(geometryOnly(), i);
      out.push_back({m.bounds(), m.triangleCount()});
    }
    return out;
  }();
  return blocks;
}

TEST(CityGenerator, SameSeedGivesTheSameBlockBitForBit) {
  const Mesh a = hlod::generateBlock(CityOptions{}, 5);
  const Mesh b = hlod::generateBlock(CityOptions{}, 5);
  ASSERT_GT(a.triangleCount(), 0u);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.texCoords, b.texCoords);
  EXPECT_EQ(a.indices, b.indices);
  ASSERT_TRUE(a.texture && b.texture);
  EXPECT_EQ(a.texture->pixels, b.texture->pixels);
}

TEST(CityGenerator, DifferentSeedsGiveDifferentBlocks) {
  const Mesh a = hlod::generateBlock(geometryOnly(1), 0);
  const Mesh b = hlod::generateBlock(geometryOnly(2), 0);
  EXPECT_TRUE(a.positions != b.positions || a.indices != b.indices);
}

TEST(CityGenerator, GeometryDoesNotDependOnTexturesOrBlockCount) {
  CityOptions many = geometryOnly();
  many.blocks = 1000;
  const Mesh a = hlod::generateBlock(geometryOnly(), 3);
  const Mesh b = hlod::generateBlock(many, 3);
  const Mesh c = hlod::generateBlock(CityOptions{}, 3);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.positions, c.positions);
  EXPECT_EQ(a.indices, c.indices);
  EXPECT_FALSE(a.texture);
}

TEST(CityGenerator, DefaultCityHasAtLeastTwoMillionTriangles) {
  std::size_t total = 0;
  for (const auto& b : defaultCityBlocks()) total += b.triangles;
  EXPECT_GE(total, 2000000u);
  EXPECT_LE(total, 4000000u);  // and stays a default that loads in reasonable time
}

TEST(CityGenerator, TriangleCountGrowsLinearlyWithBlockCount) {
  const auto& blocks = defaultCityBlocks();
  std::size_t first16 = 0, all64 = 0;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    if (i < 16) first16 += blocks[i].triangles;
    all64 += blocks[i].triangles;
  }
  const double ratio = static_cast<double>(all64) / static_cast<double>(first16);
  EXPECT_GT(ratio, 3.0);
  EXPECT_LT(ratio, 5.0);
  // Blocks far out in a big city are as dense as the first ones.
  std::size_t far = 0;
  for (int i = 600; i < 616; ++i) far += hlod::generateBlock(geometryOnly(), i).triangleCount();
  EXPECT_GT(far, first16 * 6 / 10);
  EXPECT_LT(far, first16 * 14 / 10);
}

TEST(CityGenerator, BlocksDoNotOverlapInPlan) {
  const auto& blocks = defaultCityBlocks();
  constexpr double eps = 1e-6;
  for (std::size_t i = 0; i < blocks.size(); ++i)
    for (std::size_t j = i + 1; j < blocks.size(); ++j) {
      const auto& a = blocks[i].bounds;
      const auto& b = blocks[j].bounds;
      const double ox = std::min(a.max.x, b.max.x) - std::max(a.min.x, b.min.x);
      const double oy = std::min(a.max.y, b.max.y) - std::max(a.min.y, b.min.y);
      EXPECT_FALSE(ox > eps && oy > eps) << "blocks " << i << " and " << j << " overlap";
    }
}

TEST(CityGenerator, BlocksAreStreetSidesAtRealWorldScale) {
  for (int i = 0; i < 8; ++i) {
    const auto& box = defaultCityBlocks()[static_cast<std::size_t>(i)].bounds;
    const glm::dvec3 size = box.size();
    const double length = std::max(size.x, size.y), depth = std::min(size.x, size.y);
    EXPECT_GT(length, 40.0) << i;
    EXPECT_LT(length, 300.0) << i;
    EXPECT_GT(depth, 14.0) << i;
    EXPECT_LT(depth, 100.0) << i;  // half street + buildings (+ half the courtyard east/west)
    EXPECT_NEAR(box.min.z, 0.0, 1e-9) << i;  // street level
    EXPECT_GT(box.max.z, 6.0) << i;          // at least one two-storey building
    EXPECT_LT(box.max.z, 120.0) << i;
  }
}

TEST(CityGenerator, NormalsAreUnitAndTexCoordsInsideTheTexture) {
  for (int i : {0, 1, 2, 3, 77}) {
    const Mesh m = hlod::generateBlock(geometryOnly(), i);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    ASSERT_EQ(m.texCoords.size(), m.positions.size());
    for (const auto& n : m.normals) {
      ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
      ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f);
    }
    for (const auto& t : m.texCoords) {
      ASSERT_GE(t.x, 0.0f);
      ASSERT_LE(t.x, 1.0f);
      ASSERT_GE(t.y, 0.0f);
      ASSERT_LE(t.y, 1.0f);
    }
    for (auto idx : m.indices) ASSERT_LT(idx, m.positions.size());
  }
}

TEST(CityGenerator, FacesAreWoundOutwardsAlongTheirNormals) {
  // The triangle's own normal agrees with its vertex normals (flat-shaded facets), except for
  // the slightly displaced wall panels, which still agree in sign.
  const Mesh m = hlod::generateBlock(geometryOnly(), 1);
  std::size_t disagree = 0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const auto a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
    const glm::dvec3 fn =
        glm::cross(m.positions[b] - m.positions[a], m.positions[c] - m.positions[a]);
    if (glm::dot(fn, glm::dvec3(m.normals[a] + m.normals[b] + m.normals[c])) <= 0.0) ++disagree;
  }
  EXPECT_EQ(disagree, 0u);
}

TEST(CityGenerator, TextureShowsBluishGlassWhereTheFacadeHasWindows) {
  const Mesh m = hlod::generateBlock(CityOptions{}, 0);
  ASSERT_TRUE(m.texture);
  const hlod::Image& img = *m.texture;
  EXPECT_GE(img.width, 512);
  ASSERT_EQ(img.pixels.size(), static_cast<std::size_t>(img.width) * img.height * 4);
  // Upper-floor triangles that face a street (horizontal normal): the texel under each centre is
  // glass (dark, blue-ish) for the window panes, facade colours for the rest.
  std::size_t facing = 0, glass = 0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const auto a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
    const glm::dvec3 centre = (m.positions[a] + m.positions[b] + m.positions[c]) / 3.0;
    if (centre.z < 5.0 || std::abs(m.normals[a].z) > 0.1f) continue;
    const glm::vec2 uv = (m.texCoords[a] + m.texCoords[b] + m.texCoords[c]) / 3.0f;
    const int x = std::min(img.width - 1, static_cast<int>(uv.x * img.width));
    const int y = std::min(img.height - 1, static_cast<int>(uv.y * img.height));
    const std::uint8_t* p = &img.pixels[(static_cast<std::size_t>(y) * img.width + x) * 4];
    ASSERT_EQ(p[3], 255);
    ++facing;
    const int lum = (p[0] * 3 + p[1] * 6 + p[2]) / 10;
    if (lum < 110 && p[2] > p[0] + 10) ++glass;
  }
  ASSERT_GT(facing, 1000u);
  EXPECT_GT(glass, facing / 50);
  EXPECT_LT(glass, facing / 2);
}

TEST(CityGenerator, AnchorsAreNearTheOrigin) {
  const auto o = hlod::cityToLatLon({0, 0, 0});
  EXPECT_DOUBLE_EQ(o.lat, hlod::kCityOriginLat);
  EXPECT_DOUBLE_EQ(o.lon, hlod::kCityOriginLon);
  const auto p = hlod::cityToLatLon({1000, 1000, 0});  // 1 km east and north
  EXPECT_NEAR(p.lat - o.lat, 1000.0 / 111320.0, 1e-4);
  EXPECT_NEAR(p.lon - o.lon, 1000.0 / (111320.0 * std::cos(37.87 * M_PI / 180)), 1e-4);
  EXPECT_EQ(hlod::cityBlockName(7), "block_0007");
}

TEST(CityFolder, WritesByteIdenticalFilesForTheSameSeed) {
  TempDir a, b;
  CityOptions o;
  o.blocks = 2;
  o.seed = 42;
  ASSERT_TRUE(hlod::writeCity(a.path() / "x", o).ok());
  ASSERT_TRUE(hlod::writeCity(b.path() / "x", o).ok());
  for (const char* f :
       {"city.json", "block_0000.ply", "block_0000.png", "block_0001.ply", "block_0001.png"}) {
    const std::string da = readFile(a.path() / "x" / f), db = readFile(b.path() / "x" / f);
    EXPECT_FALSE(da.empty()) << f;
    EXPECT_TRUE(da == db) << f << " differs";
  }
  EXPECT_FALSE(fs::exists(a.path() / "x" / "city.json.tmp"));
}

TEST(CityFolder, ManifestRoundTripsAndBlocksLoadBack) {
  TempDir dir;
  CityOptions o;
  o.blocks = 3;
  o.seed = 9;
  int calls = 0;
  ASSERT_TRUE(hlod::writeCity(dir.path(), o, [&](const hlod::CityProgress& p) {
                ++calls;
                EXPECT_EQ(p.blocksDone, calls);
                EXPECT_EQ(p.blocksTotal, 3);
              }).ok());
  EXPECT_EQ(calls, 3);
  EXPECT_TRUE(hlod::isCityFolder(dir.path()));

  auto m = hlod::readCityManifest(dir.path());
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->seed, 9u);
  EXPECT_DOUBLE_EQ(m->origin.lat, hlod::kCityOriginLat);
  ASSERT_EQ(m->blocks.size(), 3u);
  std::size_t total = 0;
  for (int i = 0; i < 3; ++i) {
    const Mesh g = hlod::generateBlock(geometryOnly(9), i);
    const auto& b = m->blocks[static_cast<std::size_t>(i)];
    EXPECT_EQ(b.name, hlod::cityBlockName(i));
    EXPECT_EQ(b.mesh, dir.path() / (b.name + ".ply"));
    EXPECT_EQ(b.texture, dir.path() / (b.name + ".png"));
    EXPECT_EQ(b.triangles, g.triangleCount());
    EXPECT_EQ(b.bounds.min, g.bounds().min);
    EXPECT_EQ(b.bounds.max, g.bounds().max);
    const auto anchor = hlod::cityToLatLon(g.bounds().centre());
    EXPECT_DOUBLE_EQ(b.anchor.lat, anchor.lat);
    EXPECT_DOUBLE_EQ(b.anchor.lon, anchor.lon);
    total += b.triangles;
  }
  EXPECT_EQ(m->triangles, total);

  auto block = hlod::loadCityBlock(*m, 1);
  ASSERT_TRUE(block.ok()) << block.message();
  const Mesh g = hlod::generateBlock(geometryOnly(9), 1);
  EXPECT_EQ(block->name, "block_0001");
  EXPECT_EQ(block->triangleCount(), g.triangleCount());
  EXPECT_EQ(block->positions, g.positions);  // double positions survive the PLY round trip
  ASSERT_TRUE(block->texture);
  EXPECT_EQ(block->texture->width, hlod::kDefaultCityTextureSize);
  EXPECT_FALSE(hlod::loadCityBlock(*m, 3).ok());

  auto city = hlod::loadCity(dir.path());
  ASSERT_TRUE(city.ok()) << city.message();
  EXPECT_EQ(city->meshes.size(), 3u);
  EXPECT_EQ(city->triangleCount(), total);
}

// A valid one-block folder whose manifest the test then breaks.
std::string oneBlockManifest(const std::string& mesh) {
  return R"({"format":"hlodr-city","version":1,"seed":1,"blocks":[{"name":"b","mesh":")" + mesh +
         R"(","texture":"","triangles":1,"bounds":[[0,0,0],[1,1,1]],"anchor":{"lat":37.87,"lon":-122.27}}],"origin":{"lat":37.87,"lon":-122.27},"triangles":1})";
}

TEST(CityFolder, ReadsAHandWrittenManifest) {
  TempDir dir;
  writeFile(dir.path() / "b.ply", "ply\n");
  writeFile(dir.path() / "city.json", oneBlockManifest("b.ply"));
  auto m = hlod::readCityManifest(dir.path());
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->blocks.at(0).mesh, dir.path() / "b.ply");
  EXPECT_TRUE(m->blocks.at(0).texture.empty());
}

TEST(CityFolder, RejectsMalformedJson) {
  TempDir dir;
  writeFile(dir.path() / "city.json", "{\"format\": \"hlodr-city\", \"blocks\": [");
  auto m = hlod::readCityManifest(dir.path());
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.message().find("not valid JSON"), std::string::npos) << m.message();
}

TEST(CityFolder, RejectsPathsThatEscapeTheFolder) {
  TempDir dir;
  writeFile(dir.path() / "b.ply", "ply\n");
  for (const std::string bad : {"../b.ply", "sub/../../b.ply", "/etc/passwd"}) {
    writeFile(dir.path() / "city.json", oneBlockManifest(bad));
    auto m = hlod::readCityManifest(dir.path());
    ASSERT_FALSE(m.ok()) << bad;
    EXPECT_TRUE(m.message().find("escapes") != std::string::npos ||
                m.message().find("absolute") != std::string::npos)
        << m.message();
  }
}

TEST(CityFolder, RejectsMissingBlockFilesAndFields) {
  TempDir dir;
  writeFile(dir.path() / "city.json", oneBlockManifest("gone.ply"));
  auto missing = hlod::readCityManifest(dir.path());
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("gone.ply"), std::string::npos) << missing.message();
  EXPECT_NE(missing.message().find("missing"), std::string::npos) << missing.message();

  writeFile(dir.path() / "city.json",
            R"({"format":"hlodr-city","version":1,"blocks":[{"name":"b"}]})");
  auto noMesh = hlod::readCityManifest(dir.path());
  ASSERT_FALSE(noMesh.ok());
  EXPECT_NE(noMesh.message().find("mesh"), std::string::npos) << noMesh.message();

  writeFile(dir.path() / "city.json", R"({"format":"other","version":1,"blocks":[]})");
  EXPECT_FALSE(hlod::readCityManifest(dir.path()).ok());
  writeFile(dir.path() / "city.json", R"({"format":"hlodr-city","version":2,"blocks":[]})");
  EXPECT_FALSE(hlod::readCityManifest(dir.path()).ok());
  writeFile(dir.path() / "b.ply", "ply\n");
  std::string badBounds = oneBlockManifest("b.ply");
  badBounds.replace(badBounds.find("[[0,0,0],[1,1,1]]"), 17, "[[0,0,0],[1,1]]");
  writeFile(dir.path() / "city.json", badBounds);
  EXPECT_FALSE(hlod::readCityManifest(dir.path()).ok());
}

TEST(CityFolder, IsCityFolderNeedsCityJson) {
  TempDir dir;
  EXPECT_FALSE(hlod::isCityFolder(dir.path()));
  EXPECT_FALSE(hlod::isCityFolder(dir.path() / "nope"));
  EXPECT_FALSE(hlod::readCityManifest(dir.path()).ok());
  EXPECT_FALSE(hlod::loadCity(dir.path()).ok());
}

TEST(CityFolder, WriteCityReportsBadArguments) {
  TempDir dir;
  CityOptions o;
  o.blocks = 0;
  EXPECT_FALSE(hlod::writeCity(dir.path(), o).ok());
  o.blocks = hlod::kMaxCityBlocks + 1;
  EXPECT_FALSE(hlod::writeCity(dir.path(), o).ok());
  o.blocks = 1;
  writeFile(dir.path() / "file", "x");
  auto s = hlod::writeCity(dir.path() / "file", o);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("file"), std::string::npos) << s.message();
}

TEST(CityWriter, TheSizeEstimateIsAnUpperBoundCloseToWhatIsWritten) {
  TempDir dir;
  CityOptions o;
  o.blocks = 2;
  ASSERT_TRUE(hlod::writeCity(dir.path(), o));
  std::uintmax_t written = 0;
  for (const auto& e : fs::directory_iterator(dir.path())) written += fs::file_size(e.path());
  const std::uint64_t estimate = hlod::estimateCityBytes(o);
  EXPECT_GE(estimate, written);
  EXPECT_LE(double(estimate), 1.5 * double(written));
  o.blocks = 100000;  // the figure the free-space check compares: about 270 GB
  EXPECT_GT(hlod::estimateCityBytes(o), 200'000'000'000ULL);
}

}  // namespace
