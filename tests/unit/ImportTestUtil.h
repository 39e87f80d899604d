#pragma once
// Helpers shared by the import tests: a per-test temporary folder and file writers.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

namespace hlod::testing {

// A fresh folder under the system temp dir, removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string("hlodr-import-") + (info ? info->test_suite_name() : "x") + "-" +
                       (info ? info->name() : "y") + "-" + std::to_string(::getpid());
    path_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::filesystem::path file(const std::string& name) const { return path_ / name; }

  // Writes bytes (text or binary) and returns the path.
  std::filesystem::path write(const std::string& name, const std::string& bytes) const {
    const auto p = file(name);
    std::FILE* f = std::fopen(p.c_str(), "wb");
    if (f) {
      std::fwrite(bytes.data(), 1, bytes.size(), f);
      std::fclose(f);
    }
    return p;
  }

 private:
  std::filesystem::path path_;
};

// Appends a scalar in little- or big-endian byte order.
template <class T>
void putBytes(std::string& out, T value, bool bigEndian = false) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if (bigEndian)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

}  // namespace hlod::testing
