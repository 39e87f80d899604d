// insideFolder: the check that keeps a model's references (textures, materials, buffers, city
// blocks) inside the model's folder, links included.
#include "hlod/import/InsideFolder.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace {

namespace fs = std::filesystem;

class InsideFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    root = fs::temp_directory_path() /
           ("hlodr_inside_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(root);
    model = root / "model";
    fs::create_directories(model / "sub");
    fs::create_directories(root / "outside");
    std::ofstream(model / "sub" / "tex.png") << "x";
    std::ofstream(root / "outside" / "secret.txt") << "x";
  }
  void TearDown() override { fs::remove_all(root); }
  bool inside(const std::string& ref) { return hlod::insideFolder(model, ref).ok(); }
  fs::path root, model;
};

TEST_F(InsideFolder, PathsInTheFolderAndBelowAreInside) {
  EXPECT_TRUE(inside("sub/tex.png"));
  EXPECT_TRUE(inside("./sub/../sub/tex.png"));
  EXPECT_TRUE(inside("missing.png"));  // existence is the caller's question
  EXPECT_TRUE(inside("sub/missing/deeper.png"));
  auto r = hlod::insideFolder(model, "sub/tex.png");
  ASSERT_TRUE(r) << r.message();
  EXPECT_EQ(*r, fs::canonical(model / "sub" / "tex.png"));
}

TEST_F(InsideFolder, AbsoluteAndClimbingPathsAreOutside) {
  EXPECT_FALSE(inside((root / "outside" / "secret.txt").string()));
  EXPECT_FALSE(inside((model / "sub" / "tex.png").string()));  // absolute, even if inside
  EXPECT_FALSE(inside("../outside/secret.txt"));
  EXPECT_FALSE(inside("sub/../../outside/secret.txt"));
  EXPECT_FALSE(inside(".."));
  EXPECT_FALSE(inside(""));
}

TEST_F(InsideFolder, LinksThatLeaveTheFolderOrLeadNowhereAreOutside) {
  fs::create_symlink(root / "outside" / "secret.txt", model / "file-link");
  fs::create_directory_symlink(root / "outside", model / "dir-link");
  fs::create_symlink(model / "no-such-file", model / "dangling");
  EXPECT_FALSE(inside("file-link"));
  EXPECT_FALSE(inside("dir-link/secret.txt"));
  EXPECT_FALSE(inside("dangling"));
  // For the system "dir-link/.." would be the outside folder's parent; taken lexically it is the
  // model folder again, and the path returned (what gets opened) lies inside it.
  auto r = hlod::insideFolder(model, "dir-link/../outside/secret.txt");
  ASSERT_TRUE(r) << r.message();
  EXPECT_EQ(*r, fs::canonical(model) / "outside" / "secret.txt");
}

TEST_F(InsideFolder, LinksThatStayInsideAreFollowed) {
  fs::create_symlink("sub/tex.png", model / "alias.png");
  fs::create_directory_symlink("sub", model / "textures");
  auto r = hlod::insideFolder(model, "alias.png");
  ASSERT_TRUE(r) << r.message();
  EXPECT_EQ(*r, fs::canonical(model / "sub" / "tex.png"));
  EXPECT_TRUE(inside("textures/tex.png"));
}

TEST_F(InsideFolder, TheMessageNamesTheReferenceButNotWhatIsOutside) {
  const auto existing = hlod::insideFolder(model, "../outside/secret.txt");
  const auto missing = hlod::insideFolder(model, "../outside/nothing.txt");
  ASSERT_FALSE(existing);
  ASSERT_FALSE(missing);
  EXPECT_NE(existing.message().find("'../outside/secret.txt'"), std::string::npos);
  std::string renamed = missing.message();
  renamed.replace(renamed.find("nothing"), 7, "secret");
  EXPECT_EQ(existing.message(), renamed);
}

TEST_F(InsideFolder, AModelFolderReachedThroughALinkIsStillItsOwnFolder) {
  fs::create_directory_symlink(model, root / "model-link");
  EXPECT_TRUE(hlod::insideFolder(root / "model-link", "sub/tex.png").ok());
  EXPECT_FALSE(hlod::insideFolder(root / "model-link", "../outside/secret.txt").ok());
}

}  // namespace
