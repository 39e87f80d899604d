#pragma once
// A ZIP archive of listed files, stored (not compressed: GLB and PNG barely shrink), made as it
// is sent: its size is known before the first byte, its headers come from the FileList (sizes
// and CRC-32s), and its file data is read from the folder a piece at a time, so that a large
// tileset is never held in memory or written twice. PKWARE's APPNOTE.TXT 6.3 (sec. 4.3): local
// file header and data per file, then the central directory and its end record; names are
// UTF-8 (flag bit 11). No ZIP64: at most 65535 files and every offset below 4 GiB.
#include <cstddef>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "hlod/Result.h"
#include "server/FileList.h"

namespace service::server {

class StoredZip {
 public:
  // The archive of `files` (names relative to dir), each dated `modified` (UTC). An Error past
  // ZIP's limits without ZIP64.
  static hlod::Result<StoredZip> make(const std::filesystem::path& dir, const FileList& files,
                                      std::time_t modified);
  std::uint64_t size() const { return size_; }
  // Appends bytes [offset, offset + length) of the archive to out (at most to its end); an Error
  // when a file is gone or no longer has its listed size.
  hlod::Status read(std::uint64_t offset, std::size_t length, std::string& out) const;

 private:
  // The archive as pieces in order: header bytes, or a listed file's data.
  struct Piece {
    std::uint64_t start = 0;
    std::string bytes;           // header bytes, when path is empty
    std::filesystem::path path;  // a file's data
    std::uint64_t fileSize = 0;  // its listed size
    std::uint64_t size() const { return path.empty() ? bytes.size() : fileSize; }
  };
  std::vector<Piece> pieces_;
  std::uint64_t size_ = 0;
};

}  // namespace service::server
