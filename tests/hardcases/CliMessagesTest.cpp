// Errors that once said too little: an option value without the option or its range, a camera
// value that is not finite reported as a wrong count, a usage without the reason, a malformed
// calibration file ignored, a city without blocks built into an empty store, and progress that
// reached only a terminal.
#include <string>

#include "HardcaseFolder.h"

namespace {

using hardcase::Folder;
namespace fs = std::filesystem;

class CliMessages : public Folder {
 protected:
  void SetUp() override {
    Folder::SetUp();
    model = write("t.off", hardcase::tetraOff());
  }
  gltest::Run build(const fs::path& input, const std::string& env = "") {
    return gltest::runHlodr("build " + input.string() + " -o " + (dir / "s.hlod").string(), env);
  }
  fs::path model;
};

TEST_F(CliMessages, CalibrateNamesTheOptionAndItsRange) {
  const auto blocks = gltest::runHlodr("calibrate --blocks 0");
  EXPECT_EQ(blocks.status, 2) << blocks.output;
  EXPECT_TRUE(mentions(blocks, "--blocks: 0 is outside [1, 256]")) << blocks.output;
  const auto size = gltest::runHlodr("calibrate --size 640");
  EXPECT_EQ(size.status, 2) << size.output;
  EXPECT_TRUE(mentions(size, "--size must look like 1280x720")) << size.output;
}

TEST_F(CliMessages, RenderSaysWhichCameraValueIsNotFinite) {
  const std::string render = "render " + model.string() + " -o " + (dir / "x.png").string();
  const auto nan = gltest::runHlodr(render + " --camera 0,0,nan,1,1,1");
  EXPECT_EQ(nan.status, 2) << nan.output;
  EXPECT_TRUE(mentions(nan, "--camera: PZ is 'nan', not a finite number")) << nan.output;
  const auto huge = gltest::runHlodr(render + " --camera 0,0,0,1e999,1,1");
  EXPECT_TRUE(mentions(huge, "--camera: TX is '1e999', not a finite number")) << huge.output;
  const auto five = gltest::runHlodr(render + " --camera 0,0,0,1,1");
  EXPECT_TRUE(mentions(five, "--camera needs six numbers PX,PY,PZ,TX,TY,TZ, not '0,0,0,1,1'"))
      << five.output;
  const auto same = gltest::runHlodr(render + " --camera 1,2,3,1,2,3");
  EXPECT_TRUE(mentions(same, "the position and the target are the same point")) << same.output;
}

TEST_F(CliMessages, RenderSaysWhatIsMissingBeforeTheUsage) {
  const auto noOutput = gltest::runHlodr("render " + model.string());
  EXPECT_EQ(noOutput.status, 2);
  EXPECT_EQ(noOutput.output.rfind("hlodr render: an output is required", 0), 0u) << noOutput.output;
  EXPECT_TRUE(mentions(noOutput, "usage: hlodr render")) << noOutput.output;
  const auto noModel = gltest::runHlodr("render -o x.png");
  EXPECT_EQ(noModel.output.rfind("hlodr render: no MODEL given", 0), 0u) << noModel.output;
}

TEST_F(CliMessages, AMalformedCalibrationFileIsAnErrorNamingIt) {
  const fs::path calibration = write("calibration.json", "{\"cTex\": ");
  const auto r = build(model, "HLODR_CALIBRATION=" + calibration.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(mentions(r, "calibration file " + calibration.string() + " is not a JSON object"))
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "s.hlod"));
}

TEST_F(CliMessages, AMissingCalibrationFileMeansTheDefault) {
  const auto r = build(model, "HLODR_CALIBRATION=" + (dir / "none.json").string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(mentions(r, "c_tex 0.600 from default")) << r.output;
}

TEST_F(CliMessages, ACityWithoutBlocksIsRefusedAtBuild) {
  write("city/city.json", R"({"format": "hlodr-city", "version": 1, "blocks": []})");
  const auto r = build(dir / "city");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(mentions(r, "lists no blocks: no triangles to build a store from")) << r.output;
  EXPECT_FALSE(fs::exists(dir / "s.hlod"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2);
}

TEST_F(CliMessages, ProgressReachesALogAsWholeLines) {
  // runHlodr captures stderr through a pipe: not a terminal.
  const auto city = gltest::runHlodr("city --blocks 3 --texture 64 -o " + (dir / "c").string());
  ASSERT_EQ(city.status, 0) << city.output;
  EXPECT_TRUE(mentions(city, "city: 100%  3/3 blocks")) << city.output;
  EXPECT_FALSE(mentions(city, "\r")) << city.output;
  const auto b = build(model);
  ASSERT_EQ(b.status, 0) << b.output;
  EXPECT_TRUE(mentions(b, "build: 100%  1/1 blocks")) << b.output;
}

TEST_F(CliMessages, ACityLargerThanTheFreeDiskIsRefusedBeforeAnythingIsWritten) {
  const auto free = fs::space(dir).available;
  if (free > 300'000'000'000ULL) GTEST_SKIP() << "the disk has room for 100,000 blocks";
  // timeout: should the check be lost, stop long before the disk fills.
  const auto r =
      gltest::runHlodr("city --blocks 100000 --quiet -o " + (dir / "big").string(), "timeout 20");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(mentions(r, "writing 100000 blocks takes about ")) << r.output;
  EXPECT_TRUE(mentions(r, " GB free")) << r.output;
  EXPECT_FALSE(fs::exists(dir / "big"));
}

}  // namespace
