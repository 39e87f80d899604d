// The view-dependent section of the node store (vdr.bin): round trip, every size checked on
// decoding, `--vdr` builds; and the run time on it: the cluster skeleton, the active cluster
// list, the clusters' arrays and the bound chosen for the budget.
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "BuildTestMeshes.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/runtime/VdrSelector.h"
#include "hlod/store/NodeStore.h"
#include "hlod/store/VdrStore.h"
#include "hlod/vdr/ErrorBoundControl.h"
#include "hlod/vdr/VdrRuntime.h"

namespace hlod {
namespace {

namespace fs = std::filesystem;

fs::path tempDir(const std::string& name) {
  const fs::path p =
      fs::temp_directory_path() / ("hlodr-vdr-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

vdr::VdrObject texturedGrid() {
  Mesh m = testmesh::wavyGrid(16, 10.0, glm::dvec3(6.0e6, 0, 0));  // far from the origin
  m.texture = testmesh::checkerTexture(8, 8);
  auto o = vdr::buildVdrObject(m);
  EXPECT_TRUE(o) << o.message();
  return *o;
}

TEST(VdrStore, ARecordRoundTripsEveryField) {
  const vdr::VdrObject o = texturedGrid();
  auto back = decodeVdrObject(encodeVdrObject(o));
  ASSERT_TRUE(back) << back.message();
  const vdr::VertexHierarchy &a = o.hierarchy, &b = back->hierarchy;
  EXPECT_EQ(b.leafCount, a.leafCount);
  EXPECT_EQ(b.children, a.children);
  EXPECT_EQ(b.parent, a.parent);
  EXPECT_EQ(b.leafOf, a.leafOf);
  EXPECT_EQ(b.error, a.error);
  EXPECT_EQ(b.radius, a.radius);
  EXPECT_EQ(b.faces, a.faces);
  EXPECT_EQ(b.neighbourhoodStart, a.neighbourhoodStart);
  EXPECT_EQ(b.storedFaces, a.storedFaces);
  EXPECT_EQ(back->clusters.clusterOf, o.clusters.clusterOf);
  ASSERT_EQ(back->clusters.clusters.size(), o.clusters.clusters.size());
  for (std::size_t c = 0; c < o.clusters.clusters.size(); ++c) {
    EXPECT_EQ(back->clusters.clusters[c].children, o.clusters.clusters[c].children);
    EXPECT_EQ(back->clusters.errorRatio(std::uint32_t(c)), o.clusters.errorRatio(std::uint32_t(c)));
  }
  EXPECT_EQ(back->wedgeLeaf, o.wedgeLeaf);
  EXPECT_EQ(back->wedgeChart, o.wedgeChart);
  EXPECT_EQ(back->faceWedges, o.faceWedges);
  EXPECT_EQ(back->leafWedgeStart, o.leafWedgeStart);
  ASSERT_TRUE(back->texture);
  EXPECT_EQ(back->texture->pixels, o.texture->pixels);
  // Positions are stored as floats around the centre: 6,000 km away they still hold to 1e-6 m.
  for (std::uint32_t l = 0; l < a.leafCount; ++l)
    EXPECT_NEAR(glm::length(b.leafPosition[l] - a.leafPosition[l]), 0.0, 1e-5);
}

TEST(VdrStore, EveryCutAndEverySampledFlipIsAnErrorOrASafeObject) {
  const std::vector<std::byte> bytes = encodeVdrObject(texturedGrid());
  for (std::size_t n = 0; n < bytes.size(); n += 1 + n / 64)
    EXPECT_FALSE(decodeVdrObject(std::span(bytes).first(n))) << "cut at " << n;
  std::mt19937 rng(7);
  int decoded = 0;
  for (int i = 0; i < 300; ++i) {
    std::vector<std::byte> bad = bytes;
    bad[rng() % bad.size()] ^= std::byte(1u << (rng() % 8));
    auto o = decodeVdrObject(bad);
    if (!o) continue;
    ++decoded;
    // What decodes is safe to refine all the way down and back.
    vdr::ActiveMesh mesh(o->hierarchy);
    vdr::ErrorProjection all;
    all.perspective = false;
    vdr::refineToBound(mesh, mesh.activeVertices(), all, -1.0);
    vdr::refineToBound(mesh, mesh.activeVertices(), all, 1e30);
  }
  EXPECT_GT(decoded, 0);  // flips of normals, texels and errors are data, not structure
}

TEST(VdrStore, ImpossibleCountsAreRefusedBeforeAnythingIsAllocated) {
  std::vector<std::byte> bytes = encodeVdrObject(texturedGrid());
  // Leaves (the 4th u32) claimed at 2^27: the size check refuses it.
  const std::uint32_t huge = 1u << 27;
  std::memcpy(bytes.data() + 12, &huge, 4);
  auto o = decodeVdrObject(bytes);
  ASSERT_FALSE(o);
  EXPECT_NE(o.message().find("counts"), std::string::npos) << o.message();
}

TEST(VdrStore, TheIndexRoundTripsAndRefusesRecordsOutsideTheFile) {
  VdrEntry e;
  e.rootNode = 3;
  e.offset = 10;
  e.storedSize = 20;
  e.rawSize = 40;
  e.checksum = 0xabcdef;
  e.bounds.extend({1, 2, 3});
  e.bounds.extend({4, 5, 6});
  e.faces = 7, e.vertices = 8, e.clusters = 9;
  const std::vector<VdrEntry> entries{e};
  std::vector<std::byte> bytes = encodeVdrIndex(entries, 30);
  const std::span<const std::byte> index = std::span(bytes).first(bytes.size() - 24);
  auto back = decodeVdrIndex(index, 30, 4);
  ASSERT_TRUE(back) << back.message();
  ASSERT_EQ(back->size(), 1u);
  EXPECT_EQ((*back)[0].rootNode, 3u);
  EXPECT_EQ((*back)[0].checksum, 0xabcdefu);
  EXPECT_EQ((*back)[0].bounds.max, glm::dvec3(4, 5, 6));
  EXPECT_FALSE(decodeVdrIndex(index, 29, 4));  // the record would reach into the index
  EXPECT_FALSE(decodeVdrIndex(index, 30, 3));  // no node 3
  std::vector<std::byte> flipped(index.begin(), index.end());
  flipped[20] ^= std::byte(1);
  EXPECT_FALSE(decodeVdrIndex(flipped, 30, 4));  // the checksum
}

class VdrStoreBuild : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = tempDir(testing::UnitTest::GetInstance()->current_test_info()->name());
    store_ = dir_ / "model.hlod";
    Model m;
    Mesh grid = testmesh::wavyGrid(30, 10.0, glm::dvec3(6.0e6, 0, 0));
    grid.texture = testmesh::checkerTexture(16, 16);
    m.meshes.push_back(grid);
    m.meshes.push_back(testmesh::sphere(16, 24));
    BuildOptions o;
    o.desiredTri = 100;
    o.maxBlockTriangles = 1000;  // the grid's 1,800 triangles make two blocks sharing a seam
    o.vdr = true;
    auto built = buildStoreFromModel(m, store_, o);
    ASSERT_TRUE(built) << built.message();
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_, store_;
};

TEST_F(VdrStoreBuild, EveryBlockGetsAnObjectNamingItsRootNode) {
  auto store = NodeStore::open(store_);
  ASSERT_TRUE(store) << store.message();
  const auto& entries = (*store)->vdrEntries();
  const std::vector<std::uint32_t> roots = (*store)->skeleton().blockRoots();
  ASSERT_EQ(entries.size(), roots.size());
  std::uint64_t faces = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    EXPECT_EQ(entries[i].rootNode, roots[i]);
    auto o = (*store)->loadVdrObject(i);
    ASSERT_TRUE(o) << o.message();
    EXPECT_EQ(o->hierarchy.faces.size(), entries[i].faces);
    faces += entries[i].faces;
  }
  EXPECT_EQ(faces, 2u * 30 * 30 + 2u * 24 * 15);  // the grid and the sphere, whole
}

TEST_F(VdrStoreBuild, BlocksCutFromOneMeshKeepTheirSeamAtEveryBound) {
  // The grid was cut into two blocks: the positions they share are locked in both, so the
  // coarsest front of each still has them and no crack opens between the blocks.
  auto store = NodeStore::open(store_);
  ASSERT_TRUE(store);
  std::vector<std::set<std::array<double, 3>>> kept;
  for (std::size_t i = 0; i < (*store)->vdrEntries().size(); ++i) {
    auto o = (*store)->loadVdrObject(i);
    ASSERT_TRUE(o);
    vdr::ActiveMesh coarsest(o->hierarchy);
    std::set<std::array<double, 3>> at;
    // Stored as floats around each object's own centre: equal to a millimetre.
    for (std::uint32_t v : coarsest.activeVertices()) {
      const glm::dvec3 p = glm::round(o->hierarchy.position(v) * 1000.0);
      at.insert({p.x, p.y, p.z});
    }
    kept.push_back(at);
  }
  ASSERT_GE(kept.size(), 3u);
  std::size_t shared = 0;
  for (std::size_t i = 0; i < kept.size(); ++i)
    for (std::size_t j = i + 1; j < kept.size(); ++j) {
      std::size_t n = 0;
      for (const auto& p : kept[i]) n += kept[j].count(p);
      shared = std::max(shared, n);
    }
  EXPECT_GE(shared, 31u);  // the seam: a grid row or column of 31 positions
}

TEST_F(VdrStoreBuild, AStoreWithoutTheSectionOpensAndTheRuntimeSaysWhy) {
  const fs::path plain = dir_ / "plain.hlod";
  Model m;
  m.meshes.push_back(testmesh::sphere(8, 12));
  ASSERT_TRUE(buildStoreFromModel(m, plain, BuildOptions{}));
  auto store = NodeStore::open(plain);
  ASSERT_TRUE(store);
  EXPECT_TRUE((*store)->vdrEntries().empty());
  auto runtime = vdr::VdrRuntime::open(**store);
  ASSERT_FALSE(runtime);
  EXPECT_NE(runtime.message().find("--vdr"), std::string::npos);
  // A vdr store is replaced by a rebuild (vdr.bin is part of a store).
  EXPECT_TRUE(buildStoreFromModel(m, store_, BuildOptions{}));
  EXPECT_FALSE(fs::exists(store_ / "vdr.bin"));
}

TEST_F(VdrStoreBuild, ACorruptRecordIsAnErrorWhenLoaded) {
  {
    std::fstream f(store_ / "vdr.bin", std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(5);
    f.put('\x5a');
  }
  auto store = NodeStore::open(store_);
  ASSERT_TRUE(store);  // the index is intact
  auto o = (*store)->loadVdrObject(0);
  ASSERT_FALSE(o);
  EXPECT_NE(o.message().find("checksum"), std::string::npos) << o.message();
}

TEST_F(VdrStoreBuild, TheClusterSkeletonMirrorsTheClusterHierarchies) {
  auto store = NodeStore::open(store_);
  ASSERT_TRUE(store);
  auto runtime = vdr::VdrRuntime::open(**store);
  ASSERT_TRUE(runtime) << runtime.message();
  const Skeleton& sk = (*runtime)->skeleton();
  ASSERT_EQ(sk.roots.size(), (*runtime)->objectCount());
  for (std::uint32_t n = 0; n < sk.nodes.size(); ++n) {
    const NodeInfo& info = sk.nodes[n];
    for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c) {
      EXPECT_GT(c, n);
      EXPECT_EQ(sk.nodes[c].parent, n);
      EXPECT_EQ(sk.nodes[c].level, info.level + 1);
    }
  }
  // Each object's first cluster holds the whole object.
  for (std::size_t i = 0; i < (*runtime)->objectCount(); ++i) {
    const Aabb all = (*runtime)->object(i).bounds();
    const Aabb& root = sk.nodes[sk.roots[i]].bounds;
    EXPECT_LE(root.min.x, all.min.x);
    EXPECT_GE(root.max.z, all.max.z);
  }
}

TEST_F(VdrStoreBuild, ClusterArraysDrawExactlyTheFront) {
  auto store = NodeStore::open(store_);
  ASSERT_TRUE(store);
  auto runtime = vdr::VdrRuntime::open(**store);
  ASSERT_TRUE(runtime);
  vdr::VdrRuntime& rt = **runtime;
  Camera cam;
  cam.position = {6.0e6 - 2, -2, 3};
  cam.target = {6.0e6 + 5, 5, 0};
  rt.refine(vdr::ErrorProjection::of(cam, 720), 1.0);
  // Every cluster's arrays, in both forms: the faces of the front, each once, at their corners.
  std::uint64_t drawn = 0, live = 0;
  for (std::size_t i = 0; i < rt.objectCount(); ++i) live += rt.mesh(i).liveFaceCount();
  for (std::uint32_t c = 0; c < rt.skeleton().nodes.size(); ++c) {
    vdr::ArrayForm form{};
    const LocalMesh full = rt.clusterArrays(c, 0.0, &form);
    EXPECT_EQ(form, vdr::ArrayForm::VertexArray);
    const LocalMesh compact = rt.clusterArrays(c, 2.0, &form);
    EXPECT_EQ(form, vdr::ArrayForm::Compacted);
    EXPECT_EQ(full.indices.size(), compact.indices.size());
    EXPECT_LE(compact.positions.size(), full.positions.size());
    EXPECT_EQ(full.indices.size() / 3, rt.skeleton().nodes[c].numTri);
    for (std::size_t k = 0; k < full.indices.size(); ++k) {
      ASSERT_LT(full.indices[k], full.positions.size());
      EXPECT_EQ(full.positions[full.indices[k]], compact.positions[compact.indices[k]]);
    }
    drawn += full.indices.size() / 3;
  }
  EXPECT_EQ(drawn, live);
  // A refinement changes some clusters' versions, not others'.
  std::vector<std::uint64_t> before;
  for (std::uint32_t c = 0; c < rt.skeleton().nodes.size(); ++c) before.push_back(rt.version(c));
  cam.position = {6.0e6 + 12, 12, 2};
  rt.refine(vdr::ErrorProjection::of(cam, 720), 1.0);
  int changed = 0;
  for (std::uint32_t c = 0; c < rt.skeleton().nodes.size(); ++c)
    changed += rt.version(c) != before[c];
  EXPECT_GT(changed, 0);
  EXPECT_LT(changed, int(rt.skeleton().nodes.size()));
}

TEST(VdrBoundControl, OneStepReachesTheTargetOfAnInverseSquareCostModel) {
  // cost = 1e6 / bound^2: from 4 px (62,500) to a target of 10,000, the bound is 10 px.
  vdr::ErrorBoundControl control;
  EXPECT_DOUBLE_EQ(control.bound(), 4.0);
  const double bound = control.step(1e6 / 16.0, 1e4);
  EXPECT_NEAR(bound, 10.0, 1e-9);
  // Within 5% of the target it stays; the step is at most 4x; the range holds.
  EXPECT_DOUBLE_EQ(control.step(1.04e4, 1e4), 10.0);
  EXPECT_DOUBLE_EQ(control.step(1e9, 1e4), 40.0);
  for (int i = 0; i < 20; ++i) control.step(1e12, 1.0);
  EXPECT_DOUBLE_EQ(control.bound(), control.params().maxPx);
  EXPECT_DOUBLE_EQ(control.step(0.0, 1e4), control.params().maxPx);  // nothing drawn: no step
}

TEST_F(VdrStoreBuild, TheSelectorFitsTheBudgetThroughTheBound) {
  auto store = NodeStore::open(store_);
  ASSERT_TRUE(store);
  auto runtime = vdr::VdrRuntime::open(**store);
  ASSERT_TRUE(runtime);
  SelectorParams params;
  params.lakhia.c_targetTime = 30.0;
  VdrSelector selector(**runtime, params);
  EXPECT_TRUE(selector.budgeted());
  EXPECT_FALSE(selector.remakeable());  // FrameDriver::start probes it with its own frames
  View view;
  view.camera.position = {6.0e6 - 3, -3, 4};
  view.camera.target = {6.0e6 + 5, 5, 0};
  view.viewportHeight = 720;
  // A simulated GPU at 0.05 and 0.1 ms per unit of cost: the budget buys 600 and 300 units
  // (the whole grid costs 1,080: 1,800 textured triangles at c_tex 0.6).
  for (double msPerCost : {0.05, 0.1}) {
    selector.setVTime(msPerCost);
    Selection s;
    for (int frame = 0; frame < 8; ++frame) {
      s = selector.select(view, AllResident());
      selector.feedback(msPerCost * s.estimatedCost);
    }
    const double target = 30.0 / msPerCost;
    EXPECT_NEAR(s.estimatedCost / target, 1.0, 0.15) << msPerCost << " ms per cost";
    EXPECT_GT(s.errorBoundPx, 0.0);
    EXPECT_EQ(s.activeClusters, (*runtime)->activeClusterCount());
    for (std::uint32_t c : s.front) EXPECT_GT((*runtime)->skeleton().nodes[c].numTri, 0u);
  }
  EXPECT_EQ(selector.name(), "vdr");
}

}  // namespace
}  // namespace hlod
