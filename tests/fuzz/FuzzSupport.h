#pragma once
// What the fuzz targets share: a temporary folder of this process for the importers (which
// read files, as a user's model is read), and splitting one input into the files of a model.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

namespace fuzz {

// TMPDIR/hlodr-fuzz-PID, made on first use and removed at exit: per process, so that fuzzers
// running side by side (libFuzzer -jobs, or ctest -j) never read each other's files.
inline const std::filesystem::path& tempFolder() {
  struct Folder {
    std::filesystem::path path;
    Folder() {
      const char* tmp = std::getenv("TMPDIR");
      path = std::filesystem::path(tmp && *tmp ? tmp : "/tmp") /
             ("hlodr-fuzz-" + std::to_string(::getpid()));
      std::filesystem::create_directories(path);
    }
    ~Folder() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static Folder folder;
  return folder.path;
}

// Writes bytes to tempFolder() / name (replacing what a previous input left) and returns the path.
inline std::filesystem::path writeFile(const std::string& name, std::string_view bytes) {
  const auto path = tempFolder() / name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();  // the fuzzer's own set-up failed: stop, it is not the input's fault
  if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size()) std::abort();
  std::fclose(f);
  return path;
}

inline void removeFile(const std::string& name) {
  std::error_code ec;
  std::filesystem::remove(tempFolder() / name, ec);
}

inline std::string_view view(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// An input of several files: the text before the first `separator` line, and what follows it
// (empty, with `found` false, when there is none). Lets one input carry a model and its
// companion (OBJ + MTL, glTF + buffer), so that the fuzzer mutates both.
struct Split {
  std::string_view first, second;
  bool found = false;
};
inline Split splitAt(std::string_view input, std::string_view separator) {
  const auto at = input.find(separator);
  if (at == std::string_view::npos) return {input, {}, false};
  return {input.substr(0, at), input.substr(at + separator.size()), true};
}

// With HLODR_FUZZ_VERBOSE set, prints what a boundary said of the input (ok, or its error): to
// see why a seed is rejected. Silent otherwise, so that fuzzing runs at full speed.
template <class R>
void report(const char* what, const R& result) {
  static const bool verbose = std::getenv("HLODR_FUZZ_VERBOSE") != nullptr;
  if (!verbose) return;
  if (result.ok())
    std::fprintf(stderr, "%s: ok\n", what);
  else
    std::fprintf(stderr, "%s: %s\n", what, result.message().c_str());
}

}  // namespace fuzz
