// The model frame in skeleton.bin (format version 4): the up axis and the CRS round-trip, forged
// values are refused with a message, a store of an older version asks to be rebuilt, and the
// builder takes the up axis from the input's convention unless --up (BuildOptions::up) says.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cstring>
#include <filesystem>

#include "BuildTestMeshes.h"
#include "StoreBytes.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/store/NodeStore.h"

using namespace hlod;
using hlod::test::fixChecksum;
namespace fs = std::filesystem;

namespace {

Skeleton oneNodeSkeleton() {
  Skeleton s;
  s.params.levelFactor = 3.0;
  s.params.desiredTri = 800;
  s.params.cTex = 0.5;
  s.params.simplifier = "meshopt";
  NodeInfo n;
  n.bounds.extend(glm::dvec3(-1.0));
  n.bounds.extend(glm::dvec3(1.0));
  n.numTri = 12;
  n.payloadSize = 100;
  n.memoryBytes = 400;
  s.nodes.push_back(n);
  s.roots.push_back(0);
  return s;
}

StoreFacts oneNodeFacts() {
  StoreFacts f;
  f.inputTriangles = 12;
  f.blockCount = 1;
  f.payloadBytes = 100;
  return f;
}

// Byte offset of the up axis: magic, version, byte order mark, levelFactor, desiredTri, c_tex,
// the simplifier name, input triangles, block count, build seconds, payload bytes.
std::size_t upOffset(const Skeleton& s) {
  return 8 + 4 + 4 + 8 + 4 + 8 + 4 + s.params.simplifier.size() + 8 + 4 + 8 + 8;
}

void putU32(std::vector<std::byte>& bytes, std::size_t at, std::uint32_t v) {
  std::memcpy(bytes.data() + at, &v, 4);
}

}  // namespace

TEST(SkeletonFrame, UpAxisAndCrsRoundTrip) {
  for (UpAxis up : {UpAxis::X, UpAxis::Y, UpAxis::Z}) {
    Skeleton s = oneNodeSkeleton();
    s.up = up;
    s.crs.epsg = 7415;
    s.crs.description = "EPSG:7415 (projected): coordinates kept as they are";
    s.crs.toEnu = true;
    s.crs.originLat = 51.9;
    s.crs.originLon = 4.46;
    s.crs.originHeight = -3.5;
    auto d = decodeSkeleton(encodeSkeleton(s, oneNodeFacts()));
    ASSERT_TRUE(d) << d.message();
    EXPECT_EQ(d->skeleton.up, up);
    EXPECT_EQ(d->skeleton.crs.epsg, 7415);
    EXPECT_EQ(d->skeleton.crs.description, s.crs.description);
    EXPECT_TRUE(d->skeleton.crs.toEnu);
    EXPECT_EQ(d->skeleton.crs.originLat, 51.9);
    EXPECT_EQ(d->skeleton.crs.originLon, 4.46);
    EXPECT_EQ(d->skeleton.crs.originHeight, -3.5);
    EXPECT_EQ(d->facts.inputTriangles, 12u);
  }
}

TEST(SkeletonFrame, TheEncoderKeepsOnlyPrintableBoundedText) {
  Skeleton s = oneNodeSkeleton();
  s.crs.description = "EPSG:4326 \x1b[31mred\x1b[0m\n" + std::string(1000, 'x');
  auto d = decodeSkeleton(encodeSkeleton(s, oneNodeFacts()));
  ASSERT_TRUE(d) << d.message();
  EXPECT_EQ(d->skeleton.crs.description.size(), kMaxCrsDescription);
  EXPECT_EQ(d->skeleton.crs.description.find('\x1b'), std::string::npos);
  EXPECT_EQ(d->skeleton.crs.description.substr(0, 14), "EPSG:4326 ?[31");
}

TEST(SkeletonFrame, AForgedUpAxisIsRejectedWithAMessage) {
  const Skeleton s = oneNodeSkeleton();
  auto bytes = encodeSkeleton(s, oneNodeFacts());
  putU32(bytes, upOffset(s), 7);
  fixChecksum(bytes);
  auto d = decodeSkeleton(bytes);
  ASSERT_FALSE(d);
  EXPECT_NE(d.message().find("up axis 7"), std::string::npos) << d.message();
}

TEST(SkeletonFrame, AnEscapeCodeInTheCrsTextIsRejected) {
  Skeleton s = oneNodeSkeleton();
  s.crs.description = "EPSG:1 A";
  auto bytes = encodeSkeleton(s, oneNodeFacts());
  // up, epsg, toEnu, three doubles, the length, then the text: its 8th byte is the 'A'.
  const std::size_t text = upOffset(s) + 4 + 4 + 4 + 24 + 4;
  ASSERT_EQ(char(bytes[text + 7]), 'A');
  bytes[text + 7] = std::byte{0x1b};
  fixChecksum(bytes);
  auto d = decodeSkeleton(bytes);
  ASSERT_FALSE(d);
  EXPECT_NE(d.message().find("printable"), std::string::npos) << d.message();
}

TEST(SkeletonFrame, ForgedCrsOriginAndFlagAreRejected) {
  const Skeleton s = oneNodeSkeleton();
  const auto good = encodeSkeleton(s, oneNodeFacts());
  auto flag = good;
  putU32(flag, upOffset(s) + 8, 2);  // toEnu
  fixChecksum(flag);
  EXPECT_FALSE(decodeSkeleton(flag));
  auto lat = good;
  const double north = 91.0;
  std::memcpy(lat.data() + upOffset(s) + 12, &north, 8);
  fixChecksum(lat);
  EXPECT_FALSE(decodeSkeleton(lat));
}

// The code has always refused other versions (one reader, one node record layout); a store is
// derived data, so the message says to rebuild it.
TEST(SkeletonFrame, AStoreOfTheVersionBeforeAsksToBeRebuilt) {
  auto bytes = encodeSkeleton(oneNodeSkeleton(), oneNodeFacts());
  putU32(bytes, 8, kSkeletonFormatVersion - 1);
  fixChecksum(bytes);
  auto d = decodeSkeleton(bytes);
  ASSERT_FALSE(d);
  EXPECT_NE(d.message().find("version " + std::to_string(kSkeletonFormatVersion - 1)),
            std::string::npos)
      << d.message();
  EXPECT_NE(d.message().find("rebuild"), std::string::npos) << d.message();
}

TEST(SkeletonFrame, TheBuilderStoresTheInputsUpAxisUnlessOverridden) {
  const fs::path dir = fs::temp_directory_path() / ("hlodr-frame-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  Model m;
  m.meshes.push_back(testmesh::wavyGrid(8, 4.0, glm::dvec3(0.0)));
  m.crs.epsg = 28992;
  m.crs.description = "EPSG:28992 (projected)";
  BuildOptions o;
  o.desiredTri = 40;
  auto yUp = buildStoreFromModel(m, dir / "y.hlod", o);
  ASSERT_TRUE(yUp) << yUp.message();
  m.zUp = true;
  auto zUp = buildStoreFromModel(m, dir / "z.hlod", o);
  ASSERT_TRUE(zUp) << zUp.message();
  o.up = UpAxis::X;
  auto xUp = buildStoreFromModel(m, dir / "x.hlod", o);
  ASSERT_TRUE(xUp) << xUp.message();
  for (const auto& [name, up] : {std::pair{"y.hlod", UpAxis::Y}, std::pair{"z.hlod", UpAxis::Z},
                                 std::pair{"x.hlod", UpAxis::X}}) {
    auto store = NodeStore::open(dir / name);
    ASSERT_TRUE(store) << store.message();
    EXPECT_EQ((*store)->skeleton().up, up) << name;
    EXPECT_EQ((*store)->skeleton().crs.epsg, 28992) << name;
    EXPECT_EQ((*store)->skeleton().crs.description, "EPSG:28992 (projected)") << name;
  }
  fs::remove_all(dir);
}
