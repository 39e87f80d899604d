#pragma once
// The default city's node store for the benchmarks, built once into a folder beside where the
// benchmark runs (or the store given on the command line).
#include <cstdio>
#include <filesystem>

#include "hlod/Result.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/city/City.h"

namespace bench {

// The store given, or the default city's under data/ (built the first time).
inline hlod::Result<std::filesystem::path> storeOrDefaultCity(const std::filesystem::path& given,
                                                              const std::filesystem::path& data) {
  if (!given.empty()) return given;
  const std::filesystem::path store = data / "city.hlod";
  if (std::filesystem::exists(store / "skeleton.bin")) return store;
  std::fprintf(stderr, "building the default city's store under %s ...\n", data.c_str());
  if (auto s = hlod::writeCity(data / "city", hlod::CityOptions{}); !s) return s.error();
  auto built = hlod::buildStoreFromCity(data / "city", store, hlod::BuildOptions{});
  if (!built) return built.error();
  return store;
}

}  // namespace bench
