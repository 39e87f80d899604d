// Implicit tiling: Morton indices, template URIs and subtree availability (hlod/tiles/Subtree.h;
// 3D Tiles 1.1 ImplicitTiling/AVAILABILITY.adoc gives the examples checked here).
#include <gtest/gtest.h>

#include "ImportTestUtil.h"
#include "hlod/tiles/Subtree.h"

namespace hlod::tiles {
namespace {

const SubtreeBufferLoader kNoBuffers = [](const std::string& uri) -> Result<std::string> {
  return makeError("no buffer " + uri);
};

TEST(Subtree, MortonIndicesInterleaveXLowestAsTheSpecsExamples) {
  EXPECT_EQ(mortonIndex(0b11u, 0b00u), 0b0101u);
  EXPECT_EQ(mortonIndex(0b1010u, 0b0011u), 0b01001110u);
  EXPECT_EQ(mortonIndex(0b0110u, 0b0101u), 0b00110110u);
  EXPECT_EQ(mortonIndex(0b001u, 0b010u, 0b100u), 0b100010001u);
  EXPECT_EQ(mortonIndex(0b111u, 0b000u, 0b111u), 0b101101101u);
}

TEST(Subtree, TemplateUrisTakeLevelAndCoordinates) {
  EXPECT_EQ(expandTemplate("content/{level}/{x}/{y}.glb", 3, 5, 7, 0), "content/3/5/7.glb");
  EXPECT_EQ(expandTemplate("{level}-{x}-{y}-{z}.subtree", 2, 1, 0, 3), "2-1-0-3.subtree");
  EXPECT_EQ(expandTemplate("plain.json", 2, 1, 0, 3), "plain.json");
}

TEST(Subtree, JsonSubtreeWithConstantsMakesEveryTileAvailable) {
  auto s = parseSubtree(
      R"({"tileAvailability":{"constant":1},"contentAvailability":[{"constant":1}],
          "childSubtreeAvailability":{"constant":0}})",
      4, 2, kNoBuffers);
  ASSERT_TRUE(s) << s.message();
  EXPECT_EQ(s->tiles.length, 5u);  // (4^2 - 1) / 3
  for (std::uint64_t i = 0; i < 5; ++i) EXPECT_TRUE(s->tiles.at(i));
  EXPECT_FALSE(s->tiles.at(5));
  EXPECT_EQ(s->childSubtrees.length, 16u);
  EXPECT_FALSE(s->childSubtrees.at(3));
}

TEST(Subtree, BinarySubtreeReadsBitstreamsFromItsInternalBuffer) {
  // Tiles: root and children 0 and 3 (bits 0, 1, 4); content on children only; one child subtree.
  std::string bin(16, '\0');
  bin[0] = char(0b10011);
  bin[8] = char(0b10010);
  const std::string json =
      R"({"buffers":[{"byteLength":16}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":1},
          {"buffer":0,"byteOffset":8,"byteLength":1},{"buffer":0,"byteOffset":9,"byteLength":2}],
          "tileAvailability":{"bitstream":0},"contentAvailability":[{"bitstream":1}],
          "childSubtreeAvailability":{"bitstream":2}})";
  bin[9] = char(0x80);  // child subtree 7
  std::string padded = json;
  while (padded.size() % 8) padded.push_back(' ');
  std::string bytes = "subt";
  hlod::testing::putBytes(bytes, std::uint32_t(1));
  hlod::testing::putBytes(bytes, std::uint64_t(padded.size()));
  hlod::testing::putBytes(bytes, std::uint64_t(bin.size()));
  bytes += padded + bin;
  auto s = parseSubtree(bytes, 4, 2, kNoBuffers);
  ASSERT_TRUE(s) << s.message();
  EXPECT_TRUE(s->tiles.at(0));
  EXPECT_TRUE(s->tiles.at(1));
  EXPECT_FALSE(s->tiles.at(2));
  EXPECT_TRUE(s->tiles.at(4));
  EXPECT_FALSE(s->contents[0].at(0));
  EXPECT_TRUE(s->contents[0].at(1));
  EXPECT_TRUE(s->contents[0].at(4));
  EXPECT_TRUE(s->childSubtrees.at(7));
  EXPECT_FALSE(s->childSubtrees.at(6));
}

TEST(Subtree, ExternalBuffersComeThroughTheLoader) {
  std::string requested;
  auto s = parseSubtree(
      R"({"buffers":[{"uri":"a.bin","byteLength":4}],
          "bufferViews":[{"buffer":0,"byteLength":1},{"buffer":0,"byteOffset":1,"byteLength":2}],
          "tileAvailability":{"bitstream":0},"childSubtreeAvailability":{"bitstream":1}})",
      4, 1, [&](const std::string& uri) -> Result<std::string> {
        requested = uri;
        return std::string("\x01\x00\x00\x00", 4);
      });
  ASSERT_TRUE(s) << s.message();
  EXPECT_EQ(requested, "a.bin");
  EXPECT_TRUE(s->tiles.at(0));
}

TEST(Subtree, ShortBitstreamsMissingRootsAndHugeLevelsAreErrors) {
  // A 2-level quadtree subtree needs 5 tile bits (1 byte) and 16 child bits (2 bytes).
  auto shortBits = parseSubtree(
      R"({"buffers":[{"uri":"a.bin","byteLength":2}],
          "bufferViews":[{"buffer":0,"byteLength":1},{"buffer":0,"byteOffset":1,"byteLength":1}],
          "tileAvailability":{"bitstream":0},"childSubtreeAvailability":{"bitstream":1}})",
      4, 2, [](const std::string&) -> Result<std::string> { return std::string("\x1f\xff", 2); });
  ASSERT_FALSE(shortBits);
  EXPECT_NE(shortBits.message().find("childSubtreeAvailability"), std::string::npos);
  EXPECT_FALSE(parseSubtree(R"({"tileAvailability":{"constant":0},
                                "childSubtreeAvailability":{"constant":0}})",
                            4, 2, kNoBuffers));
  EXPECT_FALSE(parseSubtree(R"({"tileAvailability":{"constant":1}})", 4, 2, kNoBuffers));
  EXPECT_FALSE(parseSubtree(R"({"tileAvailability":{"constant":1},
                                "childSubtreeAvailability":{"constant":0}})",
                            4, 17, kNoBuffers));
  EXPECT_FALSE(parseSubtree("subt\x01\x00\x00\x00", 4, 2, kNoBuffers));
  EXPECT_FALSE(parseSubtree("not json", 4, 2, kNoBuffers));
}

}  // namespace
}  // namespace hlod::tiles
