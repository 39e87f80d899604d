// 3D Tiles exports as jobs (POST /api/scenes/{id}/export-3dtiles): the tileset is served file by
// file from the job's URL (what a viewer loads) and as one ZIP, nothing outside the job's folder
// is ever served, a server restarted on the jobs folder serves it still, and a store imported
// from a tileset is listed with its source.
#include <set>

#include "../unit/TilesetTestUtil.h"
#include "ServerFixture.h"
#include "hlod/tiles/TilesetImport.h"

using namespace svctest;

namespace {

// Every content URI of the tileset (tiles' "content" and "contents"), walking its tree.
std::vector<std::string> contentUris(const json& tileset) {
  std::vector<std::string> out;
  std::vector<const json*> stack{&tileset["root"]};
  while (!stack.empty()) {
    const json* t = stack.back();
    stack.pop_back();
    if (t->contains("content")) out.push_back((*t)["content"]["uri"].get<std::string>());
    if (t->contains("contents"))
      for (const auto& c : (*t)["contents"]) out.push_back(c["uri"].get<std::string>());
    if (t->contains("children"))
      for (const auto& c : (*t)["children"]) stack.push_back(&c);
  }
  return out;
}

std::uint32_t le32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[at + i]);
  return v;
}

std::uint16_t le16(const std::string& b, std::size_t at) {
  return std::uint16_t(static_cast<unsigned char>(b[at]) | static_cast<unsigned char>(b[at + 1])
                                                               << 8);
}

// A stored ZIP's entries, by name, read as an unzipper does: the end record, the central
// directory, each entry's local header and data. Empty when any part is malformed.
std::map<std::string, std::string> unzipStored(const std::string& zip) {
  std::map<std::string, std::string> out;
  if (zip.size() < 22 || le32(zip, zip.size() - 22) != 0x06054b50) return {};
  const std::size_t end = zip.size() - 22;
  const std::size_t count = le16(zip, end + 10);
  std::size_t at = le32(zip, end + 16);
  for (std::size_t i = 0; i < count; ++i) {
    if (at + 46 > end || le32(zip, at) != 0x02014b50 || le16(zip, at + 10) != 0) return {};
    const std::size_t size = le32(zip, at + 24), nameLen = le16(zip, at + 28);
    const std::size_t local = le32(zip, at + 42);
    const std::string name = zip.substr(at + 46, nameLen);
    if (local + 30 > zip.size() || le32(zip, local) != 0x04034b50 ||
        zip.compare(local + 30, nameLen, name) != 0)
      return {};
    const std::size_t data = local + 30 + nameLen + le16(zip, local + 28);
    if (data + size > zip.size()) return {};
    out[name] = zip.substr(data, size);
    at += 46 + nameLen + le16(zip, at + 30) + le16(zip, at + 32);
  }
  return out;
}

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

class ExportTest : public ServerTest {
 protected:
  // The export's tileset as a viewer fetches it, and its ZIP: every file the ZIP holds is the
  // file its URL serves, and the tileset and every content it names are among them.
  void expectServed(const std::string& id) {
    const std::string base = "/api/jobs/" + id + "/tiles/";
    auto t = client().Get(base + "tileset.json");
    ASSERT_EQ(t->status, 200) << t->body;
    EXPECT_EQ(t->get_header_value("Content-Type"), "application/json");
    const json tileset = parse(t);
    ASSERT_TRUE(tileset.is_object());
    EXPECT_EQ(tileset["asset"]["version"], "1.1");
    ASSERT_TRUE(tileset["root"].is_object());
    const std::vector<std::string> uris = contentUris(tileset);
    ASSERT_FALSE(uris.empty());
    for (const std::string& uri : uris) {
      auto c = client().Get(base + uri);
      EXPECT_EQ(c->status, 200) << uri;
      EXPECT_EQ(c->get_header_value("Content-Type"), "model/gltf-binary") << uri;
      EXPECT_EQ(c->body.rfind("glTF", 0), 0u) << uri;
    }

    auto z = client().Get("/api/jobs/" + id + "/tiles.zip");
    ASSERT_EQ(z->status, 200) << z->body;
    EXPECT_EQ(z->get_header_value("Content-Type"), "application/zip");
    const auto entries = unzipStored(z->body);
    ASSERT_FALSE(entries.empty()) << "not a readable stored ZIP";
    std::set<std::string> expected(uris.begin(), uris.end());
    expected.insert("tileset.json");
    for (const std::string& name : expected) EXPECT_TRUE(entries.count(name)) << name;
    for (const auto& [name, bytes] : entries) {
      auto f = client().Get(base + name);
      EXPECT_EQ(f->status, 200) << name;
      EXPECT_TRUE(f->body == bytes) << name << ": the ZIP's bytes differ from the file's";
    }
  }

  // Names that try to leave the tileset's folder, or name nothing in it: 400 or 404, never a
  // file (the job's record and the system's files are the ones worth taking).
  void expectNoEscape(const std::string& id) {
    const std::string base = "/api/jobs/" + id + "/tiles/";
    for (const char* name :
         {"..%2f..%2fetc%2fpasswd", "../x", "..%2Fjob.json", "%2e%2e/job.json",
          "content/../tileset.json", "./tileset.json", "%2fetc%2fpasswd", "/etc/passwd",
          "content%5c..%5c..%5cjob.json", "%252e%252e%252fjob.json", "nothere.glb", "content",
          "content/", "%ff.glb", "tiles-list.json"}) {
      auto r = client().Get(base + name);
      EXPECT_TRUE(r->status == 400 || r->status == 404) << name << ": " << r->status;
      EXPECT_TRUE(parse(r).contains("error")) << name << ": " << r->body.substr(0, 200);
      EXPECT_EQ(r->body.find("root:"), std::string::npos) << name;
      EXPECT_EQ(r->body.find("\"record\""), std::string::npos) << name;
      EXPECT_EQ(r->body.find("\"asset\""), std::string::npos) << name;
    }
    EXPECT_EQ(client().Get(base + "..%2f..%2fetc%2fpasswd")->status, 400);
    EXPECT_EQ(client().Get(base + "nothere.glb")->status, 404);
  }
};

TEST_F(ExportTest, AnExportJobServesItsTilesetAndZipAndStillDoesAfterARestart) {
  service::ServerOptions o;
  o.jobsDir = jobsFolder();
  start(o);
  auto r = post("/api/scenes/city/export-3dtiles", json::object());
  ASSERT_EQ(r->status, 202) << r->body;
  const json submitted = parse(r);
  EXPECT_EQ(submitted["kind"], "export");
  EXPECT_EQ(submitted["scene"], "city");
  const std::string id = submitted["id"];
  const json done = waitForJob(id);
  ASSERT_EQ(done["state"], "done") << done.dump();
  EXPECT_EQ(done["progress"], 1.0);
  EXPECT_EQ(done["outputs"]["tileset"], "/api/jobs/" + id + "/tiles/tileset.json");
  EXPECT_EQ(done["outputs"]["zip"], "/api/jobs/" + id + "/tiles.zip");
  EXPECT_GT(done["result"]["contents"].get<int>(), 2);
  // Listed with the path jobs; the path jobs' own routes do not take it.
  const json jobs = parse(client().Get("/api/jobs"))["jobs"];
  ASSERT_EQ(jobs.size(), 1u);
  EXPECT_EQ(jobs[0]["id"], id);
  EXPECT_EQ(client().Get("/api/jobs/" + id + "/frames/0")->status, 404);
  // An empty body is {} too.
  auto again = client().Post("/api/scenes/city/export-3dtiles", "", "application/json");
  EXPECT_EQ(again->status, 202) << again->body;
  waitForJob(parse(again)["id"]);

  expectServed(id);
  expectNoEscape(id);
  stop();

  start(o);
  const json restored = parse(client().Get("/api/jobs/" + id));
  EXPECT_EQ(restored["state"], "done");
  EXPECT_EQ(restored["outputs"], done["outputs"]);
  expectServed(id);
  expectNoEscape(id);
  EXPECT_EQ(client().Delete("/api/jobs/" + id)->status, 204);
  EXPECT_FALSE(fs::exists(o.jobsDir / id));
  EXPECT_EQ(client().Get("/api/jobs/" + id + "/tiles/tileset.json")->status, 404);
}

TEST_F(ExportTest, AnExportOfAnUnknownSceneOrWithSettingsIsRefused) {
  start();
  auto unknown = post("/api/scenes/nope/export-3dtiles", json::object());
  EXPECT_EQ(unknown->status, 404);
  EXPECT_EQ(errorCode(unknown), "not_found");
  auto settings = post("/api/scenes/city/export-3dtiles", {{"jpeg", 80}});
  EXPECT_EQ(settings->status, 400);
  EXPECT_EQ(errorCode(settings), "bad_request");
  EXPECT_EQ(client().Get("/api/jobs/e0000000/tiles/tileset.json")->status, 404);
  EXPECT_EQ(client().Get("/api/jobs/e0000000/tiles.zip")->status, 404);
  EXPECT_TRUE(parse(client().Get("/api/jobs"))["jobs"].empty());
}

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
