// The node store: round trip, and corrupted or truncated files rejected with an Error.
#include <gtest/gtest.h>

#include <unistd.h>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include "BuildTestMeshes.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/runtime/Loader.h"
#include "hlod/store/NodeStore.h"

using namespace hlod;
namespace fs = std::filesystem;

namespace {

fs::path tempDir(const std::string& name) {
  const fs::path p =
      fs::temp_directory_path() / ("hlodr-nodestore-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

std::vector<char> readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeFile(const fs::path& p, const std::vector<char>& bytes, std::size_t n) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(n));
}

Model smallModel() {
  Model m;
  Mesh textured = testmesh::wavyGrid(24, 10.0, glm::dvec3(6.0e6, 0, 0));  // far from the origin
  textured.texture = testmesh::checkerTexture(32, 32);
  m.meshes.push_back(textured);
  m.meshes.push_back(testmesh::wavyGrid(12, 5.0, glm::dvec3(6.0e6, 20, 0)));
  return m;
}

// Every payload of the store decodes; returns the number of nodes that failed.
int failingNodes(const NodeStore& store) {
  int failed = 0;
  for (std::uint32_t i = 0; i < store.skeleton().nodes.size(); ++i)
    if (!store.loadNode(i)) ++failed;
  return failed;
}

class NodeStoreFixture : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = tempDir(testing::UnitTest::GetInstance()->current_test_info()->name());
    store_ = dir_ / "model.hlod";
    BuildOptions o;
    o.desiredTri = 150;
    o.maxBlockTriangles = 800;
    auto built = buildStoreFromModel(smallModel(), store_, o);
    ASSERT_TRUE(built) << built.message();
    skeleton_ = *built;
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_, store_;
  Skeleton skeleton_;
};

}  // namespace

TEST_F(NodeStoreFixture, RoundTripKeepsEveryNodeField) {
  auto store = NodeStore::open(store_);
  ASSERT_TRUE(store) << store.message();
  const Skeleton& s = (*store)->skeleton();
  ASSERT_EQ(s.nodes.size(), skeleton_.nodes.size());
  EXPECT_EQ(s.roots, skeleton_.roots);
  EXPECT_GT(s.roots.size(), 1u);
  EXPECT_EQ(s.params.simplifier, "meshopt");
  EXPECT_EQ(s.params.desiredTri, 150u);
  EXPECT_EQ((*store)->facts().blockCount, s.roots.size());
  EXPECT_EQ((*store)->facts().inputTriangles, smallModel().triangleCount());
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const NodeInfo &a = s.nodes[i], &b = skeleton_.nodes[i];
    EXPECT_EQ(a.parent, b.parent);
    EXPECT_EQ(a.firstChild, b.firstChild);
    EXPECT_EQ(a.childCount, b.childCount);
    EXPECT_EQ(a.bounds.min, b.bounds.min);
    EXPECT_EQ(a.bounds.max, b.bounds.max);
    EXPECT_EQ(a.centre, b.centre);
    EXPECT_EQ(a.cost, b.cost);
    EXPECT_EQ(a.staticBenefit, b.staticBenefit);
    EXPECT_EQ(a.avgNormal, b.avgNormal);
    EXPECT_EQ(a.geometricError, b.geometricError);
    EXPECT_EQ(a.payloadChecksum, b.payloadChecksum);
    EXPECT_EQ(a.textureSize, b.textureSize);
    EXPECT_EQ(a.textureChecksum, b.textureChecksum);
    EXPECT_EQ(a.textureBytes, b.textureBytes);
    auto mesh = (*store)->loadNode(std::uint32_t(i));
    ASSERT_TRUE(mesh) << mesh.message();
    EXPECT_EQ(mesh->triangleCount(), a.numTri);
    EXPECT_EQ(mesh->centre, a.centre);
    EXPECT_EQ(bool(mesh->texture), a.numTexTri > 0);
    // Float positions relative to the centre stay inside the node's box (to float precision).
    for (const auto& p : mesh->positions) {
      const glm::dvec3 w = a.centre + glm::dvec3(p);
      for (int k = 0; k < 3; ++k) {
        EXPECT_GE(w[k], a.bounds.min[k] - 1e-5);
        EXPECT_LE(w[k], a.bounds.max[k] + 1e-5);
      }
    }
  }
}

TEST_F(NodeStoreFixture, ALoaderWithoutTexturesReadsDecodesAndKeepsNoTextureBytes) {
  auto opened = NodeStore::open(store_);
  ASSERT_TRUE(opened) << opened.message();
  const NodeStore& store = **opened;
  const Skeleton& s = store.skeleton();
  std::uint64_t all = 0, mesh = 0, memory = 0, memoryWithout = 0;
  std::vector<LoadRequest> everything;
  for (std::uint32_t i = 0; i < s.nodes.size(); ++i) {
    const NodeInfo& n = s.nodes[i];
    all += n.payloadSize;
    mesh += n.payloadSize - n.textureSize;
    memory += n.memoryBytes;
    memoryWithout += n.memoryBytes - n.textureBytes;
    EXPECT_EQ(n.textureSize > 0, n.numTexTri > 0) << "node " << i;
    everything.push_back({i, 1.0 + s.nodes[i].level});
  }
  ASSERT_LT(mesh, all);  // the model's first mesh is textured
  for (bool textures : {true, false}) {
    LoaderParams p;
    p.textures = textures;
    Loader loader(store, p);
    ASSERT_TRUE(loader.loadRoots());
    loader.setWanted(everything);
    while (loader.step()) {
    }
    int texturedMeshes = 0;
    for (const LoaderEvent& e : loader.drainEvents())
      if (e.kind == LoaderEvent::Kind::Loaded) texturedMeshes += e.mesh->texture != nullptr;
    const LoaderCounters c = loader.counters();
    EXPECT_EQ(c.loadsFinished, s.nodes.size());
    EXPECT_EQ(c.bytesRead, textures ? all : mesh) << "textures " << textures;
    EXPECT_EQ(c.residentBytes, textures ? memory : memoryWithout) << "textures " << textures;
    EXPECT_EQ(texturedMeshes > 0, textures);
  }
}

TEST_F(NodeStoreFixture, EveryFlippedSkeletonByteIsAnError) {
  const auto bytes = readFile(store_ / "skeleton.bin");
  ASSERT_GT(bytes.size(), 100u);
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    auto bad = bytes;
    bad[i] = char(bad[i] ^ 0x5a);
    writeFile(store_ / "skeleton.bin", bad, bad.size());
    auto store = NodeStore::open(store_);
    EXPECT_FALSE(store) << "flip at " << i;
    if (!store) {
      EXPECT_FALSE(store.message().empty());
    }
  }
}

TEST_F(NodeStoreFixture, SkeletonCutAnywhereIsAnError) {
  const auto bytes = readFile(store_ / "skeleton.bin");
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    writeFile(store_ / "skeleton.bin", bytes, n);
    EXPECT_FALSE(NodeStore::open(store_)) << "cut at " << n;
  }
}

TEST_F(NodeStoreFixture, FlippedPayloadBytesAreCaughtByTheChecksum) {
  const auto bytes = readFile(store_ / "payload.bin");
  std::mt19937 rng(3);
  std::uniform_int_distribution<std::size_t> pos(0, bytes.size() - 1);
  for (int k = 0; k < 300; ++k) {
    auto bad = bytes;
    const std::size_t i = k < 100 ? std::size_t(k) * bytes.size() / 100 : pos(rng);
    bad[i] = char(bad[i] ^ 0x01);
    writeFile(store_ / "payload.bin", bad, bad.size());
    auto store = NodeStore::open(store_);
    ASSERT_TRUE(store);
    EXPECT_EQ(failingNodes(**store), 1) << "flip at " << i;
  }
}

TEST_F(NodeStoreFixture, TruncatedPayloadFileIsAnError) {
  const auto bytes = readFile(store_ / "payload.bin");
  for (std::size_t n : {std::size_t(0), std::size_t(1), bytes.size() / 2, bytes.size() - 1}) {
    writeFile(store_ / "payload.bin", bytes, n);
    auto store = NodeStore::open(store_);
    ASSERT_FALSE(store);
    EXPECT_NE(store.message().find("payload.bin"), std::string::npos);
  }
  fs::remove(store_ / "payload.bin");
  EXPECT_FALSE(NodeStore::open(store_));
}

TEST(NodeStorePayload, OneSidedFlagRoundTrips) {
  LocalMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  m.indices = {0, 1, 2};
  for (bool oneSided : {false, true}) {
    m.oneSided = oneSided;
    const auto bytes = encodePayload(m);
    auto back = decodePayloadBytes(bytes, glm::dvec3(0.0));
    ASSERT_TRUE(back) << back.message();
    EXPECT_EQ(back->oneSided, oneSided);
  }
}

namespace {

// One triangle with texture coordinates and a side x side checker texture.
LocalMesh texturedTriangle(int side) {
  LocalMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  m.texCoords = {{0, 0}, {1, 0}, {0, 1}};
  m.indices = {0, 1, 2};
  m.texture = testmesh::checkerTexture(side, side);
  return m;
}

}  // namespace

TEST(NodeStorePayload, ForgedPayloadsAreRejectedOrDecodedSafely) {
  const LocalMesh m = texturedTriangle(8);
  const auto good = encodePayload(m);
  auto ok = decodePayloadBytes(good, glm::dvec3(1, 2, 3));
  ASSERT_TRUE(ok) << ok.message();
  EXPECT_EQ(ok->indices, m.indices);
  EXPECT_EQ(ok->texture->pixels, m.texture->pixels);
  // Counts that disagree with the size, indices past the vertex count, NaNs: all Errors, and
  // no out-of-bounds read (run under AddressSanitizer).
  std::mt19937 rng(11);
  int rejected = 0;
  for (std::size_t i = 0; i < good.size(); ++i) {
    for (int bit : {0, 3, 7}) {
      auto bad = good;
      bad[i] = std::byte(std::uint8_t(bad[i]) ^ (1u << bit));
      auto r = decodePayloadBytes(bad, glm::dvec3(0));
      if (!r) ++rejected;
    }
  }
  EXPECT_GT(rejected, 100);
  auto idx = good;
  const std::size_t indexAt = good.size() - 8 * 8 * 4 - 12;  // the three indices
  idx[indexAt] = std::byte(7);
  EXPECT_FALSE(decodePayloadBytes(idx, glm::dvec3(0)));
  for (std::size_t n = 0; n < good.size(); ++n) {
    std::span<const std::byte> cut(good.data(), n);
    EXPECT_FALSE(decodePayloadBytes(cut, glm::dvec3(0)));
  }
}

// A quad (two triangles) with Parry's progression down to none (vertices 0 and 2 combine into 4,
// decimating both) and two splats.
LocalMesh progressiveQuad() {
  LocalMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 0}};
  m.normals.assign(5, {0, 0, 1});
  m.indices = {0, 1, 2, 0, 2, 3};
  m.progression.moves = {0, 4, 2, 4};
  m.progression.moveEnd = {2};
  m.progression.increments = {2};
  m.splats = {{{0.25f, 0.5f, 0}, 0.6f, {0, 0, 1}, {0, 0}},
              {{0.75f, 0.5f, 0}, 0.6f, {0, 0, 1}, {1, 1}}};
  return m;
}

TEST(NodeStorePayload, TheProgressionAndTheSplatsRoundTrip) {
  const LocalMesh m = progressiveQuad();
  auto back = decodePayloadBytes(encodePayload(m), glm::dvec3(0.0));
  ASSERT_TRUE(back) << back.message();
  EXPECT_EQ(back->progression.moves, m.progression.moves);
  EXPECT_EQ(back->progression.moveEnd, m.progression.moveEnd);
  EXPECT_EQ(back->progression.increments, m.progression.increments);
  ASSERT_EQ(back->splats.size(), 2u);
  EXPECT_EQ(back->splats[1].position, m.splats[1].position);
  EXPECT_EQ(back->splats[1].radius, 0.6f);
  EXPECT_EQ(back->splats[1].texCoord, m.splats[1].texCoord);
}

TEST(NodeStorePayload, AProgressionThatCouldLoopOrReachOutsideIsRejected) {
  const auto rejects = [](const Progression& p) {
    LocalMesh m = progressiveQuad();
    m.progression = p;
    return !decodePayloadBytes(encodePayload(m), glm::dvec3(0.0));
  };
  EXPECT_FALSE(rejects({{0, 4, 2, 4}, {2}, {2}}));
  EXPECT_TRUE(rejects({{0, 5, 2, 5}, {2}, {2}}));        // into a vertex past the mesh's
  EXPECT_TRUE(rejects({{0, 0}, {1}, {1}}));              // a vertex into itself
  EXPECT_TRUE(rejects({{0, 4, 4, 0}, {1, 2}, {1, 1}}));  // into a vertex already moved: a loop
  EXPECT_TRUE(rejects({{0, 4, 0, 3}, {1, 2}, {1, 0}}));  // a vertex moved twice
  EXPECT_TRUE(rejects({{0, 4, 2, 4}, {2}, {3}}));        // more decimated than there are
  EXPECT_TRUE(rejects({{0, 4, 2, 4}, {1}, {2}}));        // a move outside every combination
  EXPECT_TRUE(rejects({{0, 4, 2, 4}, {2, 1}, {1, 1}}));  // move ranges out of order
}

TEST(NodeStorePayload, StoredDeflatedAndInflatedOnlyToTheRecordedSize) {
  EXPECT_EQ(crc32(std::as_bytes(std::span("123456789", 9))), 0xcbf43926u);  // CRC-32 check value
  const LocalMesh m = texturedTriangle(64);
  const auto raw = encodePayload(m);
  const auto stored = compressPayload(raw);
  EXPECT_LT(stored.size(), raw.size() * 2 / 3);  // the checker pattern repeats: it deflates
  auto back = inflatePayload(stored, raw.size());
  ASSERT_TRUE(back) << back.message();
  EXPECT_EQ(*back, raw);
  // A wrong recorded size, an absurd one, a cut or flipped stream: Errors, never a crash.
  EXPECT_FALSE(inflatePayload(stored, raw.size() - 1));
  EXPECT_FALSE(inflatePayload(stored, raw.size() + 1));
  EXPECT_FALSE(inflatePayload(stored, ~std::uint64_t(0)));
  EXPECT_FALSE(inflatePayload(std::span(stored).first(stored.size() / 2), raw.size()));
  int rejected = 0;
  for (std::size_t i = 0; i < stored.size(); ++i) {
    auto bad = stored;
    bad[i] = std::byte(std::uint8_t(bad[i]) ^ 0x5a);
    auto r = inflatePayload(bad, raw.size());
    if (!r || *r != raw) ++rejected;
  }
  EXPECT_GT(rejected, int(stored.size() / 2));
}

TEST_F(NodeStoreFixture, ChunkReadsAreBoundsCheckedAndThreadSafe) {
  auto store = NodeStore::open(store_);
  ASSERT_TRUE(store);
  const NodeStore& s = **store;
  const auto size = s.skeleton().nodes[0].payloadSize;
  std::vector<std::byte> buf(16);
  EXPECT_FALSE(s.readPayloadChunk(0, size - 8, buf));
  EXPECT_FALSE(s.readPayloadChunk(0, ~std::uint64_t(0) - 4, buf));
  EXPECT_FALSE(s.readPayloadChunk(std::uint32_t(s.skeleton().nodes.size()), 0, buf));
  EXPECT_TRUE(s.readPayloadChunk(0, size - 16, buf));
  // Chunked reads from several threads give the same bytes as one read.
  std::vector<std::thread> threads;
  std::atomic<int> failures{0};
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&] {
      for (std::uint32_t n = 0; n < s.skeleton().nodes.size(); ++n) {
        const auto total = s.skeleton().nodes[n].payloadSize;
        std::vector<std::byte> whole(total);
        for (std::uint64_t off = 0; off < total; off += 100) {
          const auto len = std::min<std::uint64_t>(100, total - off);
          if (!s.readPayloadChunk(n, off, std::span(whole).subspan(off, len))) ++failures;
        }
        if (!s.decodePayload(n, whole)) ++failures;
      }
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(failures.load(), 0);
}

TEST(NodeStoreWriter, UnfinishedBuildLeavesNoStore) {
  const fs::path dir = tempDir("unfinished");
  {
    auto w = NodeStoreWriter::create(dir / "x.hlod");
    ASSERT_TRUE(w);
    NodeInfo n;
    ASSERT_TRUE((*w)->appendPayload(LocalMesh{}, n));
  }
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

TEST(NodeStoreWriter, RefusesToReplaceAFolderThatIsNotAStore) {
  const fs::path dir = tempDir("notastore");
  fs::create_directories(dir / "precious");
  std::ofstream(dir / "precious" / "keep.txt") << "x";
  EXPECT_FALSE(NodeStoreWriter::create(dir / "precious"));
  EXPECT_TRUE(fs::exists(dir / "precious" / "keep.txt"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);
  fs::remove_all(dir);
}

TEST(NodeStoreWriter, RefusesAFolderThatAppearedDuringTheBuild) {
  const fs::path dir = tempDir("appeared");
  auto w = NodeStoreWriter::create(dir / "x.hlod");
  ASSERT_TRUE(w);
  fs::create_directories(dir / "x.hlod");
  std::ofstream(dir / "x.hlod" / "skeleton.bin") << "someone else's";
  std::ofstream(dir / "x.hlod" / "data.csv") << "1,2";
  EXPECT_FALSE((*w)->finish(Skeleton{}, StoreFacts{}));
  EXPECT_TRUE(fs::exists(dir / "x.hlod" / "data.csv"));
  EXPECT_TRUE(fs::exists(dir / "x.hlod" / "skeleton.bin"));
  fs::remove_all(dir);
}

TEST(NodeStoreOpen, MissingStoreIsAnError) {
  auto s = NodeStore::open("/nonexistent/none.hlod");
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("not a node store"), std::string::npos);
}

// Blocks are prepared on every core and committed in order: the store does not depend on the
// thread count (the same payload bytes and node records).
class NodeStoreParallelBuild : public testing::TestWithParam<const char*> {};

TEST_P(NodeStoreParallelBuild, TwoThreadsWriteTheStoreOneThreadWrites) {
  const fs::path dir = tempDir(std::string("parallel-") + GetParam());
  Model model = smallModel();
  model.meshes.push_back(testmesh::sphere(40, 60, 3.0));
  std::vector<Skeleton> built;
  for (unsigned threads : {1u, 2u, 5u}) {
    BuildOptions o;
    o.simplifier = GetParam();
    o.desiredTri = 100;
    o.minLeafTri = 100;
    o.maxBlockTriangles = 500;
    o.threads = threads;
    auto s = buildStoreFromModel(model, dir / ("t" + std::to_string(threads)), o);
    ASSERT_TRUE(s) << s.message();
    built.push_back(*s);
  }
  ASSERT_GT(built[0].roots.size(), 6u);  // many blocks, so that the workers overlap
  const auto payload = readFile(dir / "t1" / "payload.bin");
  for (std::size_t k = 1; k < built.size(); ++k) {
    EXPECT_EQ(readFile(dir / ("t" + std::to_string(k == 1 ? 2 : 5)) / "payload.bin"), payload);
    ASSERT_EQ(built[k].nodes.size(), built[0].nodes.size());
    EXPECT_EQ(built[k].roots, built[0].roots);
    for (std::size_t i = 0; i < built[0].nodes.size(); ++i) {
      EXPECT_EQ(built[k].nodes[i].payloadOffset, built[0].nodes[i].payloadOffset);
      EXPECT_EQ(built[k].nodes[i].parent, built[0].nodes[i].parent);
      EXPECT_EQ(built[k].nodes[i].numTri, built[0].nodes[i].numTri);
      EXPECT_EQ(built[k].nodes[i].geometricError, built[0].nodes[i].geometricError);
    }
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(BothSimplifiers, NodeStoreParallelBuild,
                         testing::Values("meshopt", "openmesh"));

// An atlas every node uses all over: the nodes of a level store one texture between them (the
// union of their crops, at the level's resolution), and a loader decodes it once, hands the
// nodes one image and counts it once against its cap.
TEST(NodeStoreSharedTexture, NodesOfALevelStoreOneTextureAndTheLoaderHoldsItOnce) {
  const fs::path dir = tempDir("shared-texture");
  Mesh grid = testmesh::wavyGrid(60);  // 7,200 triangles
  for (std::size_t v = 0; v < grid.positions.size(); ++v) {
    const glm::dvec3& p = grid.positions[v];
    grid.texCoords[v] = {float(std::fmod(p.x * 7.3, 1.0)), float(std::fmod(p.y * 5.1, 1.0))};
  }
  grid.texture = testmesh::checkerTexture(64, 64);
  Model model;
  model.meshes.push_back(grid);
  BuildOptions o;
  o.desiredTri = 100;
  o.minLeafTri = 300;
  auto built = buildStoreFromModel(model, dir / "s.hlod", o);
  ASSERT_TRUE(built) << built.message();
  const Skeleton& sk = *built;
  // Per level and resolution (leaves apart): its distinct texture sections.
  std::map<std::pair<std::uint32_t, bool>, std::map<std::uint64_t, std::uint64_t>> sections;
  std::uint64_t meshes = 0;
  for (std::uint32_t i = 0; i < sk.nodes.size(); ++i) {
    const NodeInfo& n = sk.nodes[i];
    ASSERT_GT(n.textureSize, 0u) << "node " << i;
    sections[{n.level, sk.isLeaf(i)}][n.textureOffset] = n.textureBytes;
    meshes += n.memoryBytes - n.textureBytes;
  }
  std::uint64_t textures = 0;
  for (const auto& [key, offsets] : sections) {
    EXPECT_EQ(offsets.size(), 1u) << "level " << key.first << (key.second ? " leaves" : "");
    for (const auto& [offset, bytes] : offsets) {
      textures += bytes;
      EXPECT_LE(bytes, 64u * 64u * 4u);  // at most the input texture, whole
    }
  }
  const std::uint32_t leaf = sk.nodes[sk.nodes[0].firstChild].firstChild;
  ASSERT_TRUE(sk.isLeaf(leaf) && sk.isLeaf(leaf + 1));
  EXPECT_EQ(sk.nodes[leaf].textureOffset, sk.nodes[leaf + 1].textureOffset);
  EXPECT_EQ(sk.nodes[leaf].textureBytes, 64u * 64u * 4u);  // full detail at the leaves
  auto store = NodeStore::open(dir / "s.hlod");
  ASSERT_TRUE(store) << store.message();
  auto m0 = (*store)->loadNode(leaf), m1 = (*store)->loadNode(leaf + 1);
  ASSERT_TRUE(m0 && m1);
  ASSERT_TRUE(m0->texture && m1->texture);
  EXPECT_EQ(m0->texture->pixels, m1->texture->pixels);
  EXPECT_EQ(m0->texture->pixels, grid.texture->pixels);

  // Everything loaded under a cap of exactly its meshes and each texture once.
  std::vector<LoadRequest> all;
  for (std::uint32_t i = 0; i < sk.nodes.size(); ++i) all.push_back({i, 1.0 + sk.nodes[i].level});
  LoaderParams p;
  p.capBytes = meshes + textures;
  Loader loader(**store, p);
  ASSERT_TRUE(loader.loadRoots());
  loader.setWanted(all);
  while (loader.step()) {
  }
  for (std::uint32_t i = 0; i < sk.nodes.size(); ++i) ASSERT_TRUE(loader.isResident(i)) << i;
  EXPECT_EQ(loader.counters().residentBytes, meshes + textures);
  EXPECT_EQ(loader.residentPayload(leaf)->texture.get(),
            loader.residentPayload(leaf + 1)->texture.get());
  // A node whose texture was held already read only its mesh section.
  std::uint64_t payloads = 0;
  for (const NodeInfo& n : sk.nodes) payloads += n.payloadSize;
  EXPECT_LT(loader.counters().bytesRead, payloads);
  fs::remove_all(dir);
}
