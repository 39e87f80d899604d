// The build parameters in skeleton.bin come from a file: `hlodr info` once printed nan and inf
// from a forged one, and the simplifier name raw, terminal escape codes included.
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "HardcaseFolder.h"
#include "hlod/store/NodeStore.h"

namespace {

using hardcase::Folder;
namespace fs = std::filesystem;

class StoreBuildParams : public Folder {
 protected:
  void SetUp() override {
    Folder::SetUp();
    store = dir / "s.hlod";
    const auto r = gltest::runHlodr("build " + write("t.off", hardcase::tetraOff()).string() +
                                    " -o " + store.string() + " --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    original = read(store / "skeleton.bin");
  }
  // Rewrites skeleton.bin as built, with a valid checksum, after `change`.
  template <class F>
  void forge(F change) {
    const std::string& bytes = original;
    auto decoded = hlod::decodeSkeleton(
        std::span(reinterpret_cast<const std::byte*>(bytes.data()), bytes.size()));
    ASSERT_TRUE(decoded) << decoded.message();
    change(decoded->skeleton.params, decoded->facts);
    const auto out = hlod::encodeSkeleton(decoded->skeleton, decoded->facts);
    write("s.hlod/skeleton.bin",
          std::string(reinterpret_cast<const char*>(out.data()), out.size()));
  }
  gltest::Run info(const std::string& flags = "") {
    return gltest::runHlodr("info " + store.string() + flags);
  }
  fs::path store;
  std::string original;
};

TEST_F(StoreBuildParams, NonFiniteOrOutOfRangeBuildParametersAreACorruptSkeleton) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    const char* what;
    double levelFactor, cTex, seconds;
  };
  for (const Case& c : {Case{"levelFactor", nan, 0.5, 1.0}, Case{"levelFactor", 1e300, 0.5, 1.0},
                        Case{"c_tex", 3.0, inf, 1.0}, Case{"c_tex", 3.0, -0.5, 1.0},
                        Case{"build time", 3.0, 0.5, nan}, Case{"build time", 3.0, 0.5, -inf}}) {
    forge([&](hlod::BuildParams& p, hlod::StoreFacts& f) {
      p.levelFactor = c.levelFactor;
      p.cTex = c.cTex;
      f.buildSeconds = c.seconds;
    });
    const auto r = info();
    EXPECT_EQ(r.status, 1) << c.what << ": " << r.output;
    EXPECT_TRUE(mentions(r, "corrupt skeleton.bin")) << c.what << ": " << r.output;
    EXPECT_TRUE(mentions(r, c.what)) << r.output;
    EXPECT_FALSE(mentions(r, "nan") || mentions(r, "inf ")) << r.output;
  }
}

TEST_F(StoreBuildParams, ADesiredTriangleCountOfZeroIsACorruptSkeleton) {
  forge([](hlod::BuildParams& p, hlod::StoreFacts&) { p.desiredTri = 0; });
  const auto r = info();
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(mentions(r, "desiredTri")) << r.output;
}

TEST_F(StoreBuildParams, TheSimplifierNameIsPrintedWithControlCharactersEscaped) {
  forge([](hlod::BuildParams& p, hlod::StoreFacts&) { p.simplifier = "meshopt\x1b[2J\x07\xff\\"; });
  const auto text = info();
  ASSERT_EQ(text.status, 0) << text.output;
  EXPECT_EQ(text.output.find('\x1b'), std::string::npos) << text.output;
  EXPECT_TRUE(mentions(text, "simplifier meshopt\\x1b[2J\\x07\\xff\\x5c (")) << text.output;
  // The JSON form stays valid UTF-8 and parses.
  const auto jsonInfo = info(" --json");
  ASSERT_EQ(jsonInfo.status, 0) << jsonInfo.output;
  const auto parsed = nlohmann::json::parse(jsonInfo.output, nullptr, false);
  ASSERT_FALSE(parsed.is_discarded()) << jsonInfo.output;
  EXPECT_EQ(parsed["params"]["simplifier"], "meshopt\\x1b[2J\\x07\\xff\\x5c");
}

}  // namespace
