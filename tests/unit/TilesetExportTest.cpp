// A store as a 3D Tiles tileset and back (hlod/tiles/TilesetExport.h, TilesetImport.h): one GLB
// per node, boxes that hold every vertex (on every node), errors that never grow downwards,
// shared textures written once, the globe placement of a geo-referenced store, and the round
// trip store -> export -> import -> store that gives back every node.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <set>

#include "BuildTestMeshes.h"
#include "ImportTestUtil.h"
#include "TilesetSchemaCheck.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/geodesy/Geodesy.h"
#include "hlod/import/Import.h"
#include "hlod/tiles/TilesetExport.h"
#include "hlod/tiles/TilesetImport.h"
#include "tiles/TilesetFrame.h"

namespace hlod::tiles {
namespace {

namespace fs = std::filesystem;
using hlod::testing::TempDir;

nlohmann::json readJson(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in, nullptr, false);
}

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A content's positions in its tile's frame: glTF node transforms, then y-up to z-up.
tilesetcheck::ContentPositions positionsIn(const fs::path& dir) {
  return [dir](const std::string& uri, std::vector<glm::dvec3>& out) {
    const std::string bytes = readBytes(dir / uri);
    GltfBytes g;
    g.name = uri;
    g.bytes = bytes;
    g.folder = dir;
    g.baseDir = (dir / uri).parent_path();
    auto scene = importGltfBytes(g);
    if (!scene) {
      ADD_FAILURE() << scene.error().message;
      return false;
    }
    for (const Mesh& m : scene->model.meshes)
      for (const glm::dvec3& p : m.positions) out.push_back(yUpToZUp().apply(p));
    return !out.empty();
  };
}

// A grid whose every quad maps the whole texture: every node of a level uses all of it, so the
// builder stores the texture once per level and the nodes share it.
Mesh tiledGrid(int n, double size, const glm::dvec3& offset) {
  Mesh m = testmesh::wavyGrid(n, size, offset);
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x)
      m.texCoords[std::size_t(y * (n + 1) + x)] = glm::vec2(x % 2, y % 2);
  m.texture = testmesh::checkerTexture(16, 16);
  return m;
}

class TilesetExport : public ::testing::Test {
 protected:
  // Two blocks (several roots), textures owned and shared, z up; geo-referenced on request.
  void build(bool geo) {
    Model m;
    m.zUp = true;
    Mesh owned = testmesh::wavyGrid(30, 40.0);
    owned.texture = testmesh::checkerTexture(32, 32);
    m.meshes.push_back(owned);
    m.meshes.push_back(tiledGrid(30, 40.0, glm::dvec3(50.0, 0.0, 0.0)));
    m.meshes.push_back(testmesh::box({10, 60, 0}, {20, 70, 15}));
    if (geo) {
      m.crs.toEnu = true;
      m.crs.originLat = 52.0;
      m.crs.originLon = 4.4;
      m.crs.originHeight = 10.0;
      m.crs.description = "test ENU";
    }
    BuildOptions o;
    o.desiredTri = 120;
    o.minLeafTri = 200;
    o.maxBlockTriangles = 100000;
    o.threads = 1;
    auto built = buildStoreFromModel(m, dir.file("store.hlod"), o);
    ASSERT_TRUE(built) << built.message();
    auto store = NodeStore::open(dir.file("store.hlod"));
    ASSERT_TRUE(store) << store.message();
    store_ = std::move(*store);
    auto r = exportTileset(*store_, dir.file("tiles"));
    ASSERT_TRUE(r) << r.message();
    report_ = *r;
    tileset_ = readJson(dir.file("tiles/tileset.json"));
    ASSERT_TRUE(tileset_.is_object());
  }

  std::vector<const nlohmann::json*> tilesWithContent() const {
    std::vector<const nlohmann::json*> out;
    std::vector<const nlohmann::json*> stack{&tileset_["root"]};
    while (!stack.empty()) {
      const nlohmann::json* t = stack.back();
      stack.pop_back();
      if (t->contains("content")) out.push_back(t);
      if (t->contains("children"))
        for (const auto& c : (*t)["children"]) stack.push_back(&c);
    }
    return out;
  }

  TempDir dir;
  std::unique_ptr<NodeStore> store_;
  TilesetExportReport report_;
  nlohmann::json tileset_;
};

TEST_F(TilesetExport, OneGlbPerNodeAndTheTilesetPassesTheSchemaChecks) {
  build(false);
  const Skeleton& s = store_->skeleton();
  ASSERT_GT(s.roots.size(), 1u);  // several blocks: a root tile without content above them
  EXPECT_EQ(report_.contents, s.nodes.size());
  EXPECT_EQ(tilesWithContent().size(), s.nodes.size());
  EXPECT_FALSE(tileset_["root"].contains("content"));
  EXPECT_EQ(tileset_["asset"]["version"], "1.1");
  EXPECT_EQ(tileset_["root"]["refine"], "REPLACE");
  for (std::uint32_t n = 0; n < s.nodes.size(); ++n)
    EXPECT_TRUE(fs::is_regular_file(dir.file("tiles/content/n" + std::to_string(n) + ".glb")));
  tilesetcheck::Checker checker(positionsIn(dir.file("tiles")));
  for (const auto& v : checker.check(tileset_)) ADD_FAILURE() << v.rule << " at " << v.where;
}

TEST_F(TilesetExport, EveryNodesBoxHoldsEveryVertexOfItsGlb) {
  build(false);
  const auto positions = positionsIn(dir.file("tiles"));
  std::size_t checked = 0;
  for (const nlohmann::json* t : tilesWithContent()) {
    std::vector<glm::dvec3> ps;
    ASSERT_TRUE(positions((*t)["content"]["uri"], ps)) << (*t)["content"]["uri"];
    const auto& b = (*t)["boundingVolume"]["box"];
    for (const glm::dvec3& p : ps)
      for (int k = 0; k < 3; ++k) {
        const double c = b[std::size_t(k)].get<double>();
        const double h = b[std::size_t(3 + 4 * k)].get<double>();  // axis-aligned: the diagonal
        ASSERT_LE(std::abs(p[k] - c), h * (1.0 + 1e-12)) << (*t)["content"]["uri"];
      }
    ++checked;
  }
  EXPECT_EQ(checked, store_->skeleton().nodes.size());
}

TEST_F(TilesetExport, ErrorsAreTheNodesNeverGrowDownwardsAndLeavesAreZero) {
  build(false);
  const Skeleton& s = store_->skeleton();
  std::size_t leaves = 0;
  const auto walk = [&](const auto& self, const nlohmann::json& t, double parent) -> void {
    const double e = t["geometricError"].get<double>();
    EXPECT_LE(e, parent);
    if (t.contains("content")) {
      const auto n = t["extras"]["hlodr"]["node"].get<std::uint32_t>();
      if (s.nodes[n].childCount == 0) {
        EXPECT_EQ(e, 0.0);
        ++leaves;
      } else {
        EXPECT_GE(e, s.nodes[n].geometricError);
      }
    }
    if (t.contains("children"))
      for (const auto& c : t["children"]) self(self, c, e);
  };
  walk(walk, tileset_["root"], tileset_["geometricError"].get<double>());
  EXPECT_GT(leaves, 0u);
}

TEST_F(TilesetExport, ASharedTextureIsWrittenOnceAndEachNodeRefersToIt) {
  build(false);
  const Skeleton& s = store_->skeleton();
  std::map<std::uint64_t, std::size_t> users;
  for (const NodeInfo& n : s.nodes)
    if (n.textureSize > 0) ++users[n.textureOffset];
  std::size_t sharedInStore = 0;
  for (const auto& [offset, count] : users) sharedInStore += count > 1;
  ASSERT_GT(sharedInStore, 0u) << "the test store should share textures";
  EXPECT_EQ(report_.sharedTextures, sharedInStore);
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir.file("tiles/content")))
    files += e.path().filename().string().rfind("tex-", 0) == 0;
  EXPECT_EQ(files, sharedInStore);
}

TEST_F(TilesetExport, AGeoReferencedStoreSitsOnTheGlobeThroughItsRootTransform) {
  build(true);
  ASSERT_TRUE(report_.geoReferenced);
  const auto& m = tileset_["root"]["transform"];
  ASSERT_EQ(m.size(), 16u);
  glm::dmat4 t;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) t[c][r] = m[std::size_t(4 * c + r)].get<double>();
  const EnuFrame enu(LatLon{52.0, 4.4, 10.0});
  const glm::dvec3 p(12.5, -3.0, 7.0);
  const glm::dvec3 expected = enu.toEcef(p);
  EXPECT_LT(glm::length(glm::dvec3(t * glm::dvec4(p, 1.0)) - expected), 1e-6);
  // Content stays small: each node's positions are relative to its centre (RTC).
  for (const nlohmann::json* tile : tilesWithContent()) {
    const std::string bytes =
        readBytes(dir.file("tiles") / (*tile)["content"]["uri"].get<std::string>());
    const auto json = nlohmann::json::parse(
        bytes.substr(20, *reinterpret_cast<const std::uint32_t*>(bytes.data() + 12)));
    for (const auto& v : json["accessors"][0]["max"]) EXPECT_LT(std::abs(v.get<double>()), 100.0);
  }
}

void expectSameStore(const NodeStore& a, const NodeStore& b) {
  const Skeleton &x = a.skeleton(), &y = b.skeleton();
  ASSERT_EQ(x.nodes.size(), y.nodes.size());
  EXPECT_EQ(x.roots, y.roots);
  EXPECT_EQ(x.up, y.up);
  EXPECT_EQ(x.crs.toEnu, y.crs.toEnu);
  EXPECT_EQ(x.crs.originLat, y.crs.originLat);
  EXPECT_EQ(x.params.levelFactor, y.params.levelFactor);
  EXPECT_EQ(x.params.desiredTri, y.params.desiredTri);
  EXPECT_EQ(x.quadtree.domain, y.quadtree.domain);
  EXPECT_EQ(x.quadtree.cells.size(), y.quadtree.cells.size());
  for (std::uint32_t n = 0; n < x.nodes.size(); ++n) {
    SCOPED_TRACE("node " + std::to_string(n));
    const NodeInfo &p = x.nodes[n], &q = y.nodes[n];
    EXPECT_EQ(p.parent, q.parent);
    EXPECT_EQ(p.firstChild, q.firstChild);
    EXPECT_EQ(p.childCount, q.childCount);
    EXPECT_EQ(p.level, q.level);
    EXPECT_EQ(p.block, q.block);
    EXPECT_EQ(p.bounds.min, q.bounds.min);
    EXPECT_EQ(p.bounds.max, q.bounds.max);
    EXPECT_EQ(p.centre, q.centre);
    EXPECT_EQ(p.numTri, q.numTri);
    EXPECT_EQ(p.numTexTri, q.numTexTri);
    EXPECT_EQ(p.cost, q.cost);
    EXPECT_EQ(p.staticBenefit, q.staticBenefit);
    EXPECT_EQ(p.avgNormal, q.avgNormal);
    EXPECT_EQ(p.geometricError, q.geometricError);
    EXPECT_EQ(p.splatCount, q.splatCount);
    auto ma = a.loadNode(n), mb = b.loadNode(n);
    ASSERT_TRUE(ma && mb);
    EXPECT_EQ(ma->positions, mb->positions);
    EXPECT_EQ(ma->normals, mb->normals);
    EXPECT_EQ(ma->texCoords, mb->texCoords);
    EXPECT_EQ(ma->indices, mb->indices);
    EXPECT_EQ(ma->baseColor, mb->baseColor);
    EXPECT_EQ(ma->oneSided, mb->oneSided);
    ASSERT_EQ(bool(ma->texture), bool(mb->texture));
    if (ma->texture) {
      EXPECT_EQ(ma->texture->pixels, mb->texture->pixels);
    }
    ASSERT_EQ(ma->splats.size(), mb->splats.size());
  }
}

TEST_F(TilesetExport, ReadBackItIsTheStoreItCameFrom) {
  build(false);
  auto r = buildStoreFromTileset(dir.file("tiles/tileset.json"), dir.file("back.hlod"));
  ASSERT_TRUE(r) << r.message();
  EXPECT_TRUE(r->hlodrExport);
  auto back = NodeStore::open(dir.file("back.hlod"));
  ASSERT_TRUE(back) << back.message();
  expectSameStore(*store_, **back);
}

TEST_F(TilesetExport, ReadBackOnTheGlobeItIsTheStoreItCameFrom) {
  build(true);
  auto r = buildStoreFromTileset(dir.file("tiles/tileset.json"), dir.file("back.hlod"));
  ASSERT_TRUE(r) << r.message();
  auto back = NodeStore::open(dir.file("back.hlod"));
  ASSERT_TRUE(back) << back.message();
  expectSameStore(*store_, **back);
}

TEST(TilesetExportMars, AYUpStoreFromATilesetExportsValidAndReadsBackTheSame) {
  const fs::path mars = fs::path(HLODR_SHARED_DATA) / "mars-tileset/tileset.json";
  if (!fs::exists(mars)) GTEST_SKIP() << "shared data not found: " << mars;
  TempDir dir;
  auto in = buildStoreFromTileset(mars, dir.file("mars.hlod"));
  ASSERT_TRUE(in) << in.message();
  ASSERT_EQ(in->skeleton.up, UpAxis::Y);
  auto store = NodeStore::open(dir.file("mars.hlod"));
  ASSERT_TRUE(store) << store.message();
  auto out = exportTileset(**store, dir.file("tiles"));
  ASSERT_TRUE(out) << out.message();
  EXPECT_FALSE(out->geoReferenced);
  tilesetcheck::Checker checker(positionsIn(dir.file("tiles")));
  for (const auto& v : checker.check(readJson(dir.file("tiles/tileset.json"))))
    ADD_FAILURE() << v.rule << " at " << v.where;
  auto back = buildStoreFromTileset(dir.file("tiles/tileset.json"), dir.file("back.hlod"));
  ASSERT_TRUE(back) << back.message();
  auto again = NodeStore::open(dir.file("back.hlod"));
  ASSERT_TRUE(again) << again.message();
  expectSameStore(**store, **again);
}

TEST_F(TilesetExport, AFolderThatIsNoExportIsNeverReplaced) {
  build(false);
  dir.write("mine/notes.txt", "");
  fs::create_directories(dir.file("mine"));
  dir.write("mine/notes.txt", "keep");
  auto r = exportTileset(*store_, dir.file("mine"));
  ASSERT_FALSE(r);
  EXPECT_NE(r.message().find("notes.txt"), std::string::npos) << r.message();
  EXPECT_TRUE(fs::exists(dir.file("mine/notes.txt")));
  // An earlier export is replaced.
  EXPECT_TRUE(exportTileset(*store_, dir.file("tiles")));
}

TEST_F(TilesetExport, ACancelledExportStopsAndLeavesNoFolderBehind) {
  build(false);
  // Cancelled after the first node: the progress callback sets the flag the exporter checks.
  std::atomic<bool> cancel{false};
  TilesetExportOptions o;
  o.cancel = &cancel;
  std::size_t calls = 0;
  auto r = exportTileset(*store_, dir.file("again"), o, [&](std::size_t, std::size_t) {
    ++calls;
    cancel = true;
  });
  ASSERT_FALSE(r);
  EXPECT_EQ(r.message(), "cancelled");
  EXPECT_EQ(calls, 1u);
  EXPECT_FALSE(fs::exists(dir.file("again")));
  for (const auto& e : fs::directory_iterator(dir.file("")))
    EXPECT_EQ(e.path().filename().string().find("again.tmp"), std::string::npos) << e.path();
}

}  // namespace
}  // namespace hlod::tiles
