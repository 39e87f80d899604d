// Values the importers once let through: coordinates beyond what a store can hold (a build
// "succeeded" into a store that then read as corrupt) and an OBJ face index of LLONG_MIN
// (negated: undefined behaviour).
#include <string>

#include "HardcaseFolder.h"

namespace {

using hardcase::Folder;
namespace fs = std::filesystem;

class ImportRange : public Folder {
 protected:
  gltest::Run build(const fs::path& file) {
    return gltest::runHlodr("build " + file.string() + " -o " + (dir / "s.hlod").string() +
                            " --quiet");
  }
  static std::string offWith(const std::string& x) {
    return "OFF\n4 4 0\n0 0 0\n" + x + " 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  }
};

TEST_F(ImportRange, CoordinatesBeyondFloatRangeAreRefusedNamingTheFileAndTheValue) {
  const auto off = build(write("far.off", offWith("1e39")));
  EXPECT_EQ(off.status, 1) << off.output;
  EXPECT_TRUE(mentions(off, "far.off: vertex 1 has coordinate 1e+39")) << off.output;
  const auto obj = build(write("far.obj", "v 0 0 0\nv 1 0 0\nv 0 -1e100 0\nf 1 2 3\n"));
  EXPECT_EQ(obj.status, 1) << obj.output;
  EXPECT_TRUE(mentions(obj, "far.obj: vertex 2 has coordinate -1e+100")) << obj.output;
  EXPECT_FALSE(fs::exists(dir / "s.hlod"));
}

TEST_F(ImportRange, CoordinatesJustInsideTheBoundBuildIntoAStoreThatReadsBack) {
  // The widest span the bound allows: -1.6e38 to 1.6e38, whose half still fits a float.
  const auto r = build(write("wide.off",
                             "OFF\n3 1 0\n-1.6e38 0 0\n1.6e38 0 0\n0 1.6e38 0\n"
                             "3 0 1 2\n"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto info = gltest::runHlodr("info " + (dir / "s.hlod").string());
  EXPECT_EQ(info.status, 0) << info.output;
}

TEST_F(ImportRange, AnObjFaceIndexOfLlongMinIsOutOfRangeWithoutBeingNegated) {
  const auto r = build(write("min.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -9223372036854775808 1 2\n"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(mentions(r, "face index -9223372036854775808 out of range (3 vertices)")) << r.output;
}

}  // namespace
