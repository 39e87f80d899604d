// 3D Tiles tile formats: b3dm headers (current and both legacy forms), feature and batch tables,
// cmpt, and telling formats apart (hlod/tiles/TileFormats.h).
#include <gtest/gtest.h>

#include "TilesetTestUtil.h"
#include "hlod/tiles/TileFormats.h"

namespace hlod::tiles {
namespace {

using hlod::testing::b3dm;
using hlod::testing::putBytes;
using hlod::testing::squareGlb;

TEST(TileFormats, FormatsAreToldApartByMagicOrByTheirJson) {
  EXPECT_EQ(detectTileFormat(squareGlb(0, 0, 0, 1)), TileFormat::Glb);
  EXPECT_EQ(detectTileFormat(b3dm(squareGlb(0, 0, 0, 1), {{"BATCH_LENGTH", 0}})), TileFormat::B3dm);
  EXPECT_EQ(detectTileFormat("cmpt...."), TileFormat::Cmpt);
  EXPECT_EQ(detectTileFormat("i3dm...."), TileFormat::I3dm);
  EXPECT_EQ(detectTileFormat("pnts...."), TileFormat::Pnts);
  EXPECT_EQ(detectTileFormat(R"( {"asset":{"version":"1.1"},"geometricError":1,"root":{}})"),
            TileFormat::Tileset);
  EXPECT_EQ(detectTileFormat(R"({"asset":{"version":"2.0"},"meshes":[]})"), TileFormat::GltfJson);
  EXPECT_EQ(detectTileFormat("{\"asset\":"), TileFormat::Unknown);  // truncated JSON
  EXPECT_EQ(detectTileFormat("GIF89a"), TileFormat::Unknown);
}

TEST(TileFormats, B3dmGivesItsGlbBatchLengthAndRtcCentreFromAnArray) {
  const std::string glb = squareGlb(0, 0, 0, 1);
  const std::string bytes = b3dm(glb, {{"BATCH_LENGTH", 3}, {"RTC_CENTER", {1.5, -2.0, 6378137.0}}},
                                 {}, {{"id", {1, 2, 3}}});
  auto b = parseB3dm(bytes);
  ASSERT_TRUE(b) << b.message();
  EXPECT_EQ(b->glb, glb);
  EXPECT_EQ(b->batchLength, 3u);
  EXPECT_EQ(b->batchProperties, 1u);
  ASSERT_TRUE(b->rtcCenter.has_value());
  EXPECT_EQ(*b->rtcCenter, glm::dvec3(1.5, -2.0, 6378137.0));
}

TEST(TileFormats, B3dmRtcCentreAndBatchLengthMayLieInTheBinaryBody) {
  std::string body;
  putBytes(body, 10.0f);
  putBytes(body, 20.0f);
  putBytes(body, 30.0f);
  putBytes(body, std::uint32_t(7));
  auto b = parseB3dm(
      b3dm(squareGlb(0, 0, 0, 1),
           {{"BATCH_LENGTH", {{"byteOffset", 12}}}, {"RTC_CENTER", {{"byteOffset", 0}}}}, body));
  ASSERT_TRUE(b) << b.message();
  EXPECT_EQ(b->batchLength, 7u);
  EXPECT_EQ(*b->rtcCenter, glm::dvec3(10.0, 20.0, 30.0));
}

TEST(TileFormats, B3dmWithoutBatchLengthOrWithABinaryReferenceOutsideItsBodyIsAnError) {
  const std::string glb = squareGlb(0, 0, 0, 1);
  EXPECT_NE(parseB3dm(b3dm(glb, nlohmann::json::object())).message().find("BATCH_LENGTH"),
            std::string::npos);
  auto far = parseB3dm(b3dm(glb, {{"BATCH_LENGTH", 0}, {"RTC_CENTER", {{"byteOffset", 64}}}}));
  EXPECT_NE(far.message().find("outside"), std::string::npos) << far.message();
  auto batch = parseB3dm(
      b3dm(glb, {{"BATCH_LENGTH", 100}}, {},
           {{"height", {{"byteOffset", 0}, {"componentType", "FLOAT"}, {"type", "SCALAR"}}}}));
  EXPECT_NE(batch.message().find("height"), std::string::npos) << batch.message();
}

TEST(TileFormats, TruncatedB3dmSaysHowLongItClaimsToBe) {
  std::string bytes = b3dm(squareGlb(0, 0, 0, 1), {{"BATCH_LENGTH", 0}});
  bytes.resize(bytes.size() / 2);
  auto b = parseB3dm(bytes);
  ASSERT_FALSE(b);
  EXPECT_NE(b.message().find("truncated"), std::string::npos) << b.message();
  EXPECT_FALSE(parseB3dm("b3dm"));
}

TEST(TileFormats, LegacyB3dmHeadersAreRead) {
  const std::string glb = squareGlb(0, 0, 0, 1);
  // Legacy 1 (20 bytes): batchLength, batchTableByteLength; the GLB's magic follows.
  std::string one = "b3dm";
  putBytes(one, std::uint32_t(1));
  putBytes(one, std::uint32_t(20 + glb.size()));
  putBytes(one, std::uint32_t(5));  // batchLength
  putBytes(one, std::uint32_t(0));  // batch table bytes
  one += glb;
  auto a = parseB3dm(one);
  ASSERT_TRUE(a) << a.message();
  EXPECT_EQ(a->batchLength, 5u);
  EXPECT_EQ(a->glb, glb);
  // Legacy 2 (24 bytes): batchTableJSONByteLength, batchTableBinaryByteLength, batchLength.
  const std::string table = R"({"id":[1,2]})";
  std::string two = "b3dm";
  putBytes(two, std::uint32_t(1));
  putBytes(two, std::uint32_t(24 + table.size() + glb.size()));
  putBytes(two, std::uint32_t(table.size()));
  putBytes(two, std::uint32_t(0));
  putBytes(two, std::uint32_t(2));  // batchLength
  two += table + glb;
  auto b = parseB3dm(two);
  ASSERT_TRUE(b) << b.message();
  EXPECT_EQ(b->batchLength, 2u);
  EXPECT_EQ(b->glb, glb);
}

TEST(TileFormats, CmptListsItsInnerTilesAndRefusesOnesThatRunPastItsEnd) {
  const std::string inner = b3dm(squareGlb(0, 0, 0, 1), {{"BATCH_LENGTH", 0}});
  std::string c = "cmpt";
  putBytes(c, std::uint32_t(1));
  putBytes(c, std::uint32_t(16 + 2 * inner.size()));
  putBytes(c, std::uint32_t(2));
  c += inner + inner;
  auto tiles = parseCmpt(c);
  ASSERT_TRUE(tiles) << tiles.message();
  ASSERT_EQ(tiles->size(), 2u);
  EXPECT_EQ((*tiles)[1], inner);
  std::string bad = c;
  bad[12] = 3;  // three inner tiles claimed, two present
  EXPECT_FALSE(parseCmpt(bad));
}

}  // namespace
}  // namespace hlod::tiles
