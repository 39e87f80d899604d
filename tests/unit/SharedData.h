#pragma once
// The shared real-world data (../shared/data, HLODR_SHARED_DATA): a file's path, and a skip with
// the path where that file is absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace hlod::test {

inline std::filesystem::path sharedData(const std::string& name) {
  return std::filesystem::path(HLODR_SHARED_DATA) / name;
}

}  // namespace hlod::test

#define SKIP_IF_SHARED_ABSENT(name)                             \
  if (!std::filesystem::exists(::hlod::test::sharedData(name))) \
  GTEST_SKIP() << "shared data not found: " << ::hlod::test::sharedData(name)
