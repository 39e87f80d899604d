#pragma once
// A store that many test processes need: ctest runs each test in a process of its own, so a
// "build once for all tests" static builds it once per test. cachedStore builds it once per
// test binary into the build tree (HLODR_TEST_CACHE) and reuses it while that binary is
// unchanged (its mtime and size are the key, so a rebuilt builder rebuilds the store).
// Processes that build at once each write a folder of their own and race to rename it: the
// first wins, the others use its folder.
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <string>
#include <system_error>

namespace gltest {

// build(dir) fills dir (not yet there) with whatever the tests read; false on failure (an
// empty path is returned, and the test's own checks then fail on it).
inline std::filesystem::path cachedStore(
    const std::string& name, const std::function<bool(const std::filesystem::path&)>& build) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  struct stat st {};
  if (ec || ::stat(exe.c_str(), &st) != 0) return {};
  const std::string prefix = exe.filename().string() + "-" + name + "-";
  const std::string key = prefix + std::to_string(st.st_mtim.tv_sec) + "." +
                          std::to_string(st.st_mtim.tv_nsec) + "-" + std::to_string(st.st_size);
  const fs::path root = HLODR_TEST_CACHE;
  const fs::path dir = root / key;
  if (fs::is_directory(dir)) return dir;  // renamed into place only once complete
  fs::create_directories(root, ec);
  const fs::path mine = root / (key + ".building-" + std::to_string(::getpid()));
  fs::remove_all(mine, ec);
  if (!build(mine)) {
    fs::remove_all(mine, ec);
    return {};
  }
  fs::rename(mine, dir, ec);
  if (ec) {
    fs::remove_all(mine, ec);  // another process was first: its folder is the same store
    return fs::is_directory(dir) ? dir : fs::path{};
  }
  // What earlier builds of this binary left.
  for (const auto& e : fs::directory_iterator(root, ec)) {
    const std::string n = e.path().filename().string();
    if (n.rfind(prefix, 0) == 0 && n != key && n.find(".building-") == std::string::npos)
      fs::remove_all(e.path(), ec);
  }
  return dir;
}

}  // namespace gltest
