// insideFolder: the one check that keeps a model's references inside the model's folder.
#include "hlod/import/InsideFolder.h"

#include <system_error>

namespace hlod {

namespace fs = std::filesystem;

namespace {

bool within(const fs::path& p, const fs::path& base) {
  const fs::path r = p.lexically_relative(base);
  return !r.empty() && *r.begin() != "..";
}

}  // namespace

Result<fs::path> insideFolder(const fs::path& folder, const std::string& reference) {
  const fs::path where = folder.empty() ? fs::path(".") : folder;
  auto outside = [&] {
    return makeError("'" + reference + "' lies outside the model's folder " + where.string() +
                     " (a model's files are read only from its own folder)");
  };
  if (reference.empty()) return makeError("empty file name");
  const fs::path ref(reference);
  if (ref.has_root_name() || ref.has_root_directory()) return outside();
  // Lexically first: "a/../b" is b, even where a is a link (the system would climb from the
  // link's target, but what gets opened is the path returned here, not the reference), and a
  // leading ".." climbs out whatever lies on disk.
  const fs::path rel = ref.lexically_normal();
  if (rel.empty() || *rel.begin() == "..") return outside();
  std::error_code ec;
  const fs::path base = fs::canonical(where, ec);
  if (ec) return makeError("cannot resolve the model's folder " + where.string());
  // Then on disk: follow the reference one part at a time and resolve a link as soon as it is
  // met, so that the path returned holds no link and lies inside base.
  fs::path cur = base;
  for (auto part = rel.begin(); part != rel.end(); ++part) {
    if (part->empty() || *part == ".") continue;
    cur /= *part;
    const fs::file_status st = fs::symlink_status(cur, ec);
    if (st.type() == fs::file_type::not_found) {
      // Nothing further exists now, so no further link can lead out: the rest is plain names.
      for (++part; part != rel.end(); ++part) cur /= *part;
      return cur;
    }
    if (ec) return outside();  // cannot be inspected (permissions): not known to be inside
    if (fs::is_symlink(st)) {
      cur = fs::canonical(cur, ec);
      // A dangling link is refused too: "not found" would tell whether its target exists.
      if (ec || !within(cur, base))
        return makeError("'" + reference + "' goes through a link that leaves the model's folder " +
                         where.string() + " or leads nowhere");
    }
  }
  return cur;
}

}  // namespace hlod
