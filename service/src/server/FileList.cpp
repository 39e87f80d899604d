#include "server/FileList.h"

#include <algorithm>
#include <fstream>
#include <span>

#include "hlod/store/NodeStore.h"

namespace service::server {

namespace fs = std::filesystem;

namespace {

// The longest name a route takes (pathParam): a longer one could never be asked for.
constexpr std::size_t kMaxName = 256;

}  // namespace

bool FileList::isInsideName(const std::string& name) {
  if (name.empty() || name.size() > kMaxName || name.find('\\') != std::string::npos) return false;
  std::size_t start = 0;
  for (;;) {
    const std::size_t slash = name.find('/', start);
    const std::string part = name.substr(start, slash == std::string::npos ? slash : slash - start);
    if (part.empty() || part == "." || part == "..") return false;
    if (slash == std::string::npos) return true;
    start = slash + 1;
  }
}

hlod::Result<FileList> FileList::read(const fs::path& dir) {
  FileList list;
  std::error_code ec;
  // Links are not followed into folders, and a link to a file is no regular file here: only
  // what was written into the folder is listed.
  fs::recursive_directory_iterator it(dir, ec);
  if (ec) return hlod::makeError("cannot read " + dir.string() + ": " + ec.message());
  for (; it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) return hlod::makeError("cannot read " + dir.string() + ": " + ec.message());
    std::error_code e;
    if (!fs::is_regular_file(it->symlink_status(e))) continue;
    ListedFile f;
    f.name = fs::relative(it->path(), dir, e).generic_string();
    if (e || !isInsideName(f.name)) continue;
    std::ifstream in(it->path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof()) return hlod::makeError("cannot read " + it->path().string());
    f.size = bytes.size();
    f.crc32 = hlod::crc32(std::as_bytes(std::span(bytes.data(), bytes.size())));
    list.files_.push_back(std::move(f));
  }
  std::sort(list.files_.begin(), list.files_.end(),
            [](const ListedFile& a, const ListedFile& b) { return a.name < b.name; });
  return list;
}

nlohmann::json FileList::json() const {
  nlohmann::json files = nlohmann::json::array();
  for (const ListedFile& f : files_)
    files.push_back({{"name", f.name}, {"size", f.size}, {"crc32", f.crc32}});
  return {{"files", files}};
}

hlod::Result<FileList> FileList::fromJson(const nlohmann::json& j) {
  if (!j.is_object() || !j.contains("files") || !j["files"].is_array())
    return hlod::makeError("not a file list");
  FileList list;
  for (const auto& f : j["files"]) {
    if (!f.is_object() || !f.contains("name") || !f["name"].is_string() || !f.contains("size") ||
        !f["size"].is_number_unsigned() || !f.contains("crc32") ||
        !f["crc32"].is_number_unsigned() || f["crc32"].get<std::uint64_t>() > 0xffffffffu)
      return hlod::makeError("not a file list");
    ListedFile file{f["name"].get<std::string>(), f["size"].get<std::uint64_t>(),
                    f["crc32"].get<std::uint32_t>()};
    if (!isInsideName(file.name)) return hlod::makeError("a listed name leaves the folder");
    list.files_.push_back(std::move(file));
  }
  std::sort(list.files_.begin(), list.files_.end(),
            [](const ListedFile& a, const ListedFile& b) { return a.name < b.name; });
  return list;
}

const ListedFile* FileList::find(const std::string& name) const {
  const auto it =
      std::lower_bound(files_.begin(), files_.end(), name,
                       [](const ListedFile& f, const std::string& n) { return f.name < n; });
  return it != files_.end() && it->name == name ? &*it : nullptr;
}

}  // namespace service::server
