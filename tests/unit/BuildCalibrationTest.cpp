// The calibration file that carries c_tex (eq. 1) from `hlodr calibrate` to `hlodr build`.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "hlod/builder/Calibration.h"

namespace fs = std::filesystem;

namespace {

class CalibrationFile : public testing::Test {
 protected:
  void SetUp() override {
    path_ = fs::temp_directory_path() / ("hlodr-calib-" + std::to_string(::getpid())) / "c.json";
    fs::remove_all(path_.parent_path());
    const char* old = std::getenv("HLODR_CALIBRATION");
    if (old) old_ = old;
    ::setenv("HLODR_CALIBRATION", path_.c_str(), 1);
  }
  void TearDown() override {
    if (old_.empty())
      ::unsetenv("HLODR_CALIBRATION");
    else
      ::setenv("HLODR_CALIBRATION", old_.c_str(), 1);
    fs::remove_all(path_.parent_path());
  }
  fs::path path_;
  std::string old_;
};

}  // namespace

TEST_F(CalibrationFile, AMissingFileIsNoCalibrationRatherThanAnError) {
  auto c = hlod::readCalibratedCTex();
  ASSERT_TRUE(c) << c.message();
  EXPECT_FALSE(c->has_value());
}

TEST_F(CalibrationFile, WrittenValueIsReadBack) {
  ASSERT_TRUE(hlod::writeCalibration(0.73));
  auto c = hlod::readCalibratedCTex();
  ASSERT_TRUE(c) << c.message();
  ASSERT_TRUE(c->has_value());
  EXPECT_DOUBLE_EQ(**c, 0.73);
}

TEST_F(CalibrationFile, MalformedOrOutOfRangeFilesAreErrors) {
  EXPECT_FALSE(hlod::writeCalibration(1.5));
  fs::create_directories(path_.parent_path());
  for (const char* text : {"", "{", "[]", "{\"cTex\": \"a\"}", "{\"cTex\": -0.1}", "{\"x\": 1}"}) {
    std::ofstream(path_) << text;
    const auto c = hlod::readCalibratedCTex();
    ASSERT_FALSE(c) << text;
    EXPECT_NE(c.message().find(path_.string()), std::string::npos) << c.message();
  }
}
