// 3D Tiles in the server: a store imported from a tileset is listed with its source.

#include "../unit/TilesetTestUtil.h"
#include "ServerFixture.h"
#include "hlod/tiles/TilesetImport.h"

using namespace svctest;

namespace {

// A store of the data folder for one test, removed at its end (the other tests see one scene).
struct ExtraStore {
  explicit ExtraStore(fs::path p) : path(std::move(p)) { fs::remove_all(path); }
  ~ExtraStore() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  fs::path path;
};

}  // namespace

class ExportTest : public ServerTest {};

TEST_F(ExportTest, AStoreImportedFromATilesetIsListedAsFrom3dTiles) {
  makeScene();  // the data folder first (made afresh by the first test that starts a server)
  // A tileset of three squares (a root and two children), as another tool writes one.
  const fs::path src = dataDir() / "tiny-tileset";
  fs::remove_all(src);
  fs::create_directories(src);
  using hlod::testing::squareGlb;
  using hlod::testing::tile;
  std::ofstream(src / "root.glb", std::ios::binary) << squareGlb(0, 0, 0, 100);
  std::ofstream(src / "a.glb", std::ios::binary) << squareGlb(0, 0, 0, 50);
  std::ofstream(src / "b.glb", std::ios::binary) << squareGlb(50, 50, 0, 50);
  std::ofstream(src / "tileset.json")
      << hlod::testing::tileset(tile("root.glb", 10.0, {tile("a.glb", 0.0), tile("b.glb", 0.0)}))
             .dump();
  const ExtraStore store(dataDir() / "tiny.hlod");
  auto built = hlod::tiles::buildStoreFromTileset(src / "tileset.json", store.path);
  fs::remove_all(src);
  ASSERT_TRUE(built) << built.message();

  start();
  const json scenes = parse(client().Get("/api/scenes"))["scenes"];
  std::map<std::string, std::string> sources;
  for (const json& s : scenes) sources[s["id"]] = s["source"];
  EXPECT_EQ(sources["tiny"], "3d-tiles");
  EXPECT_EQ(sources["city"], "city");
}
