// Data loss: `hlodr build MODEL -o DIR` once deleted DIR's other files when DIR held any file
// named skeleton.bin. A build replaces only a node store, and only what the store consists of.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "../gl/RunHlodr.h"

namespace fs = std::filesystem;

namespace {

class BuildNeverDeletes : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("hlodr_hard_build_" + std::to_string(::getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "tetra.off")
        << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  }
  void TearDown() override { fs::remove_all(dir); }
  gltest::Run build(const fs::path& out) {
    return gltest::runHlodr("build " + (dir / "tetra.off").string() + " -o " + out.string() +
                            " --quiet");
  }
  static void write(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
  }
  static std::string read(const fs::path& p) {
    std::ifstream in(p);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  // Everything in dir's parent except the model: no temporary or moved-aside folder remains.
  std::size_t entriesBeside() const {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir)) n += e.path().filename() != "tetra.off";
    return n;
  }
  fs::path dir;
};

TEST_F(BuildNeverDeletes, AFolderWithAStraySkeletonFileKeepsAllItsFiles) {
  const fs::path work = dir / "work";
  write(work / "skeleton.bin", "my notes, not a store");
  write(work / "thesis.tex", "years of work");
  write(work / "figures" / "fig1.svg", "<svg/>");
  const auto r = build(work);
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("not part of a node store"), std::string::npos) << r.output;
  EXPECT_EQ(read(work / "thesis.tex"), "years of work");
  EXPECT_EQ(read(work / "figures" / "fig1.svg"), "<svg/>");
  EXPECT_EQ(read(work / "skeleton.bin"), "my notes, not a store");
  EXPECT_EQ(entriesBeside(), 1u);  // no temporary folder left beside it
}

TEST_F(BuildNeverDeletes, AFileNamedSkeletonBinAloneIsNotAStore) {
  const fs::path work = dir / "work";
  write(work / "skeleton.bin", "not a skeleton");
  EXPECT_NE(build(work).status, 0);
  EXPECT_EQ(read(work / "skeleton.bin"), "not a skeleton");
}

TEST_F(BuildNeverDeletes, AStoreWithAUserFileInsideIsNotReplaced) {
  const fs::path store = dir / "model.hlod";
  ASSERT_EQ(build(store).status, 0);
  write(store / "README.txt", "mine");
  EXPECT_NE(build(store).status, 0);
  EXPECT_EQ(read(store / "README.txt"), "mine");
  EXPECT_TRUE(fs::exists(store / "skeleton.bin"));
}

TEST_F(BuildNeverDeletes, APlainFileAsOutputIsKept) {
  const fs::path file = dir / "out.hlod";
  write(file, "a file");
  EXPECT_NE(build(file).status, 0);
  EXPECT_EQ(read(file), "a file");
}

TEST_F(BuildNeverDeletes, AnEarlierStoreIsReplacedWithoutLeftovers) {
  const fs::path store = dir / "model.hlod";
  ASSERT_EQ(build(store).status, 0);
  const auto r = build(store);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(gltest::runHlodr("info " + store.string()).status, 0);
  EXPECT_EQ(entriesBeside(), 1u);  // the store only: no .tmp- or .old- folder
}

}  // namespace
