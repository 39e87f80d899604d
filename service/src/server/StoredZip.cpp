#include "server/StoredZip.h"

#include <algorithm>
#include <fstream>

namespace service::server {

namespace fs = std::filesystem;

namespace {

constexpr std::uint32_t kLocalHeader = 0x04034b50;
constexpr std::uint32_t kCentralHeader = 0x02014b50;
constexpr std::uint32_t kEndOfCentral = 0x06054b50;
constexpr std::uint16_t kVersionNeeded = 10;          // 1.0: stored files, no more
constexpr std::uint16_t kMadeByUnix = (3 << 8) | 20;  // Unix, 2.0: external attributes hold modes
constexpr std::uint16_t kUtf8Names = 1 << 11;         // general purpose flag bit 11
constexpr std::uint32_t kRegularFileMode = 0100644u << 16;  // -rw-r--r--
constexpr std::uint64_t kMax32 = 0xffffffffu;

void put16(std::string& out, std::uint16_t v) {
  out.push_back(char(v & 0xff));
  out.push_back(char(v >> 8));
}

void put32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(char((v >> (8 * i)) & 0xff));
}

// MS-DOS date and time (APPNOTE 4.4.6): two-second resolution, from 1980.
std::pair<std::uint16_t, std::uint16_t> dosDateTime(std::time_t t) {
  std::tm tm{};
  gmtime_r(&t, &tm);
  if (tm.tm_year < 80) return {(1 << 5) | 1, 0};  // 1980-01-01 00:00
  const auto date = std::uint16_t(((tm.tm_year - 80) << 9) | ((tm.tm_mon + 1) << 5) | tm.tm_mday);
  const auto time = std::uint16_t((tm.tm_hour << 11) | (tm.tm_min << 5) | (tm.tm_sec / 2));
  return {date, time};
}

}  // namespace

hlod::Result<StoredZip> StoredZip::make(const fs::path& dir, const FileList& files,
                                        std::time_t modified) {
  const std::vector<ListedFile>& list = files.files();
  if (list.size() > 0xffff)
    return hlod::makeError(std::to_string(list.size()) +
                           " files, more than a ZIP without ZIP64 holds (65535)");
  const auto [date, time] = dosDateTime(modified);
  StoredZip zip;
  std::string central;
  std::uint64_t at = 0;
  const auto add = [&](Piece p) {
    p.start = at;
    at += p.size();
    zip.pieces_.push_back(std::move(p));
  };
  for (const ListedFile& f : list) {
    if (f.size > kMax32 || at > kMax32)
      return hlod::makeError("the files pass 4 GiB, more than a ZIP without ZIP64 holds");
    const auto offset = std::uint32_t(at);
    // The fields both headers share, from "version needed" to the name's length.
    std::string common;
    put16(common, kVersionNeeded);
    put16(common, kUtf8Names);
    put16(common, 0);  // stored
    put16(common, time);
    put16(common, date);
    put32(common, f.crc32);
    put32(common, std::uint32_t(f.size));  // compressed size: the same, stored
    put32(common, std::uint32_t(f.size));
    put16(common, std::uint16_t(f.name.size()));
    put16(common, 0);  // extra field length

    Piece local;
    put32(local.bytes, kLocalHeader);
    local.bytes += common + f.name;
    add(std::move(local));
    Piece data;
    data.path = dir / f.name;
    data.fileSize = f.size;
    add(std::move(data));

    put32(central, kCentralHeader);
    put16(central, kMadeByUnix);
    central += common;
    put16(central, 0);  // file comment length
    put16(central, 0);  // disk number start
    put16(central, 0);  // internal attributes
    put32(central, kRegularFileMode);
    put32(central, offset);
    central += f.name;
  }
  if (at > kMax32 || central.size() > kMax32)
    return hlod::makeError("the files pass 4 GiB, more than a ZIP without ZIP64 holds");
  const auto centralOffset = std::uint32_t(at);
  const auto centralSize = std::uint32_t(central.size());
  put32(central, kEndOfCentral);
  put16(central, 0);  // this disk
  put16(central, 0);  // the disk the central directory starts on
  put16(central, std::uint16_t(list.size()));
  put16(central, std::uint16_t(list.size()));
  put32(central, centralSize);
  put32(central, centralOffset);
  put16(central, 0);  // comment length
  Piece end;
  end.bytes = std::move(central);
  add(std::move(end));
  zip.size_ = at;
  return zip;
}

hlod::Status StoredZip::read(std::uint64_t offset, std::size_t length, std::string& out) const {
  std::uint64_t left = std::min<std::uint64_t>(length, offset < size_ ? size_ - offset : 0);
  // The piece that holds offset: the last one starting at or before it.
  auto it = std::upper_bound(pieces_.begin(), pieces_.end(), offset,
                             [](std::uint64_t o, const Piece& p) { return o < p.start; });
  for (--it; left > 0 && it != pieces_.end(); ++it) {
    const std::uint64_t from = offset - it->start;
    const std::uint64_t n = std::min(left, it->size() - from);
    if (it->path.empty()) {
      out.append(it->bytes, std::size_t(from), std::size_t(n));
    } else {
      // The listed size is in the headers already sent: a file that changed since is an error,
      // never a corrupt archive.
      std::error_code ec;
      if (fs::file_size(it->path, ec) != it->fileSize || ec)
        return hlod::makeError(it->path.filename().string() + " changed since it was listed");
      std::ifstream in(it->path, std::ios::binary);
      in.seekg(std::streamoff(from));
      const std::size_t before = out.size();
      out.resize(before + std::size_t(n));
      in.read(out.data() + before, std::streamsize(n));
      if (!in) return hlod::makeError("cannot read " + it->path.filename().string());
    }
    offset += n;
    left -= n;
  }
  return hlod::Ok{};
}

}  // namespace service::server
