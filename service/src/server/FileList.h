#pragma once
// The files of a job's output folder, listed once when the job ends: what the API serves of
// that folder is looked up here by name, never joined to the folder as the client wrote it, so
// no request reaches a file the job did not write. Also what a ZIP of the folder is made from
// (StoredZip), hence the sizes and CRC-32s.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hlod/Result.h"

namespace service::server {

struct ListedFile {
  std::string name;  // relative to the folder, '/'-separated ("content/n0.glb")
  std::uint64_t size = 0;
  std::uint32_t crc32 = 0;  // CRC-32 (IEEE, as ZIP)
};

class FileList {
 public:
  // The regular files under dir, in name order, each read once for its CRC. Links and other
  // special files are left out; an Error when dir cannot be read.
  static hlod::Result<FileList> read(const std::filesystem::path& dir);
  // The form save() writes, checked: an Error for anything else (names as isInsideName says).
  static hlod::Result<FileList> fromJson(const nlohmann::json& j);
  nlohmann::json json() const;

  const std::vector<ListedFile>& files() const { return files_; }
  const ListedFile* find(const std::string& name) const;  // null: not listed
  // A name that can only mean a file inside the folder: relative, '/'-separated, with no empty,
  // "." or ".." part and no backslash. What a route checks before the lookup, to answer 400.
  static bool isInsideName(const std::string& name);

 private:
  std::vector<ListedFile> files_;  // sorted by name
};

}  // namespace service::server
