// An image write that fails (a full disk: /dev/full behind a link) once reported success and
// exited 0, for rendered frames (PNG, BMP) and for the city's block textures alike.
#include <string>

#include "HardcaseFolder.h"

namespace {

using hardcase::Folder;
namespace fs = std::filesystem;

class ImageWriteFailure : public Folder {};

TEST_F(ImageWriteFailure, ARenderOntoAFullDiskFailsAndSaysWhy) {
  const fs::path model = write("t.off", hardcase::tetraOff());
  for (const std::string ext : {".png", ".bmp"}) {
    const fs::path out = dir / ("frame" + ext);
    fs::create_symlink("/dev/full", out);
    const auto r =
        gltest::runHlodr("render " + model.string() + " -o " + out.string() + " --size 64x64");
    EXPECT_EQ(r.status, 1) << ext << ": " << r.output;
    EXPECT_TRUE(mentions(r, "cannot write " + out.string() + ": No space left on device"))
        << r.output;
    EXPECT_TRUE(fs::is_symlink(out));  // what the link points to is not the writer's to remove
  }
}

TEST_F(ImageWriteFailure, ARenderThatWritesIsReadBackWhole) {
  const fs::path out = dir / "frame.bmp";
  const auto r = gltest::runHlodr("render " + write("t.off", hardcase::tetraOff()).string() +
                                  " -o " + out.string() + " --size 64x48");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(fs::file_size(out), 54u + 64u * 48u * 3u);  // BMP header and 24-bit rows
}

TEST_F(ImageWriteFailure, ACityWhoseTextureCannotBeWrittenFails) {
  fs::create_directories(dir / "city");
  fs::create_symlink("/dev/full", dir / "city" / "block_0000.png");
  const auto r =
      gltest::runHlodr("city --blocks 1 --texture 64 --quiet -o " + (dir / "city").string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(mentions(r, "block_0000.png: No space left on device")) << r.output;
  EXPECT_FALSE(fs::exists(dir / "city" / "city.json"));  // an incomplete city is no city
}

}  // namespace
