#include "hlod/AtomicFile.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <system_error>

namespace hlod {

namespace fs = std::filesystem;

Status writeFileAtomically(const fs::path& path, std::string_view bytes) {
  // Hidden, in the same folder (a rename within one file system), unique to this process and
  // call: two writers of one file never share a temporary.
  static std::atomic<unsigned> serial{0};
  const fs::path tmp =
      path.parent_path() / ("." + path.filename().string() + "." + std::to_string(::getpid()) +
                            "." + std::to_string(serial++) + ".partial");
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) return makeError("cannot write " + path.string() + ": " + std::strerror(errno));
  // The first failure's errno: a full disk shows at the write, the flush or only the close.
  int error = 0;
  if (std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fflush(f) != 0)
    error = errno ? errno : EIO;
  if (std::fclose(f) != 0 && error == 0) error = errno ? errno : EIO;
  std::error_code ec;
  if (error == 0) {
    fs::rename(tmp, path, ec);
    if (!ec) return Ok{};
    error = ec.value();
  }
  fs::remove(tmp, ec);
  return makeError("cannot write " + path.string() + ": " + std::strerror(error));
}

}  // namespace hlod
