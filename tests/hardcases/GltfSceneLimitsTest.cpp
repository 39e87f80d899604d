// glTF scenes that once crashed or exhausted memory: a node chain 20,000 deep (stack overflow in
// the recursive scene walk), JSON nested 20,000 deep (stack overflow in the parser), 40 nodes
// that each list the next one twice (2^40 instances), an accessor without a buffer view whose
// count no bytes back, and 200,000 instances of one quad at one place (bad_alloc in the cuts).
// Each runs under a 4 GB address-space limit, so that a regression fails fast instead of
// taking the machine's memory.
#include <string>

#include "HardcaseFolder.h"

namespace {

using hardcase::Folder;
namespace fs = std::filesystem;
using nlohmann::json;

// The command runs under `ulimit -v` (KB) and a time limit. Under AddressSanitizer, which
// reserves terabytes of address space for its shadow memory and cannot start under ulimit -v,
// its own limits do that job: an allocation over 4 GB fails (bad_alloc, as past ulimit -v) and a
// resident size over 4 GB ends the process.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)  // clang
#define HLODR_UNDER_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)  // gcc
#define HLODR_UNDER_ASAN 1
#endif
#ifdef HLODR_UNDER_ASAN
const std::string kLimits =
    "export ASAN_OPTIONS=\"$ASAN_OPTIONS:hard_rss_limit_mb=4000:max_allocation_size_mb=4000:"
    "allocator_may_return_null=1\"; timeout 400";  // ASan is 3-4 times slower; CI runs 2 at once
#else
const std::string kLimits = "ulimit -v 4000000; timeout 120";
#endif

class GltfSceneLimits : public Folder {
 protected:
  gltest::Run build(const json& gltf) {
    write("quad.bin", hardcase::quadBuffer());
    const fs::path file = write("scene.gltf", gltf.dump());
    return gltest::runHlodr(
        "build " + file.string() + " -o " + (dir / "s.hlod").string() + " --quiet", kLimits);
  }
  gltest::Run info() { return gltest::runHlodr("info " + (dir / "s.hlod").string() + " --json"); }
};

TEST_F(GltfSceneLimits, ANodeChainTwentyThousandDeepBuildsWithoutOverflowingTheStack) {
  json g = hardcase::quadGltf();
  constexpr int kDepth = 20000;
  for (int i = 0; i + 1 < kDepth; ++i)
    g["nodes"].push_back({{"children", {i + 1}}, {"translation", {0.0, 0.0, 1e-3}}});
  g["nodes"].push_back({{"mesh", 0}});
  const auto r = build(g);
  ASSERT_EQ(r.status, 0) << r.output;
  const auto i = info();
  ASSERT_EQ(i.status, 0) << i.output;
  EXPECT_EQ(json::parse(i.output)["inputTriangles"], 2) << i.output;
}

TEST_F(GltfSceneLimits, JsonNestedTwentyThousandDeepIsRefusedBeforeParsing) {
  json g = hardcase::quadGltf();
  g["nodes"].push_back({{"mesh", 0}});
  std::string text = g.dump();
  text.pop_back();  // the closing brace: add a deeply nested "extras" member
  text += ",\"extras\":" + std::string(20000, '[') + std::string(20000, ']') + "}";
  write("quad.bin", hardcase::quadBuffer());
  const fs::path file = write("deep.gltf", text);
  const auto r = gltest::runHlodr(
      "build " + file.string() + " -o " + (dir / "s.hlod").string() + " --quiet", kLimits);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(mentions(r, "deep.gltf: JSON nested deeper than")) << r.output;
}

TEST_F(GltfSceneLimits, ShallowNestingInsideStringsIsNotCountedAsDepth) {
  json g = hardcase::quadGltf();
  g["nodes"].push_back({{"mesh", 0}, {"name", std::string(5000, '[') + "\\\"{"}});
  const auto r = build(g);
  EXPECT_EQ(r.status, 0) << r.output;
}

TEST_F(GltfSceneLimits, NodesSharingChildrenCannotExpandToTwoToTheFortyInstances) {
  json g = hardcase::quadGltf();
  for (int i = 0; i < 40; ++i) g["nodes"].push_back({{"children", {i + 1, i + 1}}});
  g["nodes"].push_back({{"mesh", 0}});
  const auto r = build(g);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(mentions(r, "more than 1000000 node instances")) << r.output;
}

TEST_F(GltfSceneLimits, SharedChildrenWithinTheBoundStillBuild) {
  // Level i: node 3i lists 3i+1 and 3i+2, which both list node 3(i+1): 2^12 instances of the
  // quad, each at its own place (the left branch of level i moves by 2^(i+1)).
  json g = hardcase::quadGltf();
  constexpr int kLevels = 12;
  for (int i = 0; i < kLevels; ++i) {
    g["nodes"].push_back({{"children", {3 * i + 1, 3 * i + 2}}});
    g["nodes"].push_back(
        {{"children", {3 * (i + 1)}}, {"translation", {double(2 << i), 0.0, 0.0}}});
    g["nodes"].push_back({{"children", {3 * (i + 1)}}});
  }
  g["nodes"].push_back({{"mesh", 0}});
  const auto r = build(g);
  ASSERT_EQ(r.status, 0) << r.output;
  const auto i = info();
  EXPECT_EQ(json::parse(i.output)["inputTriangles"], 2 << kLevels) << i.output;
}

TEST_F(GltfSceneLimits, AnAccessorWithoutBufferViewCannotClaimFourBillionVertices) {
  json g = hardcase::quadGltf();
  g["accessors"][0] = {{"componentType", 5126}, {"count", 4000000000LL}, {"type", "VEC3"}};
  g["nodes"].push_back({{"mesh", 0}});
  const auto r = build(g);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(mentions(r, "more than 100000000")) << r.output;
  EXPECT_FALSE(mentions(r, "out of memory")) << r.output;
}

TEST_F(GltfSceneLimits, TwoHundredThousandInstancesOfOneQuadAtOnePlaceBuild) {
  json g = hardcase::quadGltf();
  constexpr int kCopies = 200000;
  json roots = json::array();
  for (int i = 0; i < kCopies; ++i) {
    g["nodes"].push_back({{"mesh", 0}});
    roots.push_back(i);
  }
  g["scenes"][0]["nodes"] = roots;
  const auto r = build(g);
  ASSERT_EQ(r.status, 0) << r.output;
  const auto i = info();
  ASSERT_EQ(i.status, 0) << i.output;
  const json facts = json::parse(i.output);
  EXPECT_EQ(facts["inputTriangles"], 2 * kCopies);
  // The pile cannot be separated by cuts: cutting it may not multiply its triangles.
  EXPECT_LE(facts["leafTriangles"].get<long long>(), 2LL * 2 * kCopies) << i.output;
}

}  // namespace
