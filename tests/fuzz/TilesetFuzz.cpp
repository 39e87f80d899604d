// 3D Tiles: the input is a tileset.json, then optionally files of its folder, each after a line
// "@@FILE name@@" (a plain name: letters, digits, '.', '-', '_'): contents (glb, b3dm, cmpt),
// external tilesets and subtrees. The folder is imported as `hlodr build tileset.json` does, with
// small limits; a store that results must open and every node must decode.
#include <cstdio>
#include <set>
#include <vector>

#include "FuzzSupport.h"
#include "hlod/store/NodeStore.h"
#include "hlod/tiles/TilesetImport.h"

namespace {

bool plainName(std::string_view n) {
  if (n.empty() || n.size() > 64 || n == "." || n == "..") return false;
  for (char c : n)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_'))
      return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fs = std::filesystem;
  const fs::path folder = fuzz::tempFolder() / "tileset";
  std::error_code ec;
  fs::remove_all(folder, ec);
  fs::remove_all(fuzz::tempFolder() / "out.hlod", ec);
  fs::create_directories(folder);
  std::string_view rest = fuzz::view(data, size);
  std::string name = "tileset.json";
  std::set<std::string> written;
  while (true) {
    const auto split = fuzz::splitAt(rest, "\n@@FILE ");
    if (plainName(name) && written.insert(name).second)
      fuzz::writeFile("tileset/" + name, split.first);
    if (!split.found) break;
    const auto end = split.second.find("@@\n");
    if (end == std::string_view::npos) break;
    name = std::string(split.second.substr(0, end));
    rest = split.second.substr(end + 3);
  }
  hlod::tiles::TilesetImportOptions options;
  options.limits.maxTiles = 2000;
  options.limits.maxDepth = 24;
  options.limits.maxImplicitLevels = 8;
  options.limits.maxJsonBytes = 1 << 20;
  options.maxContentBytes = 1 << 20;
  const fs::path store = fuzz::tempFolder() / "out.hlod";
  auto r = hlod::tiles::buildStoreFromTileset(folder / "tileset.json", store, options);
  fuzz::report("buildStoreFromTileset", r);
  if (!r.ok()) return 0;
  auto opened = hlod::NodeStore::open(store);
  if (!opened.ok()) {  // a store the import wrote must read back
    std::fprintf(stderr, "the imported store does not open: %s\n", opened.message().c_str());
    std::abort();
  }
  const hlod::Skeleton& s = (*opened)->skeleton();
  if (s.nodes.size() != r->nodes || s.roots.empty()) std::abort();
  for (std::uint32_t n = 0; n < s.nodes.size(); ++n)
    if (!(*opened)->loadNode(n).ok()) std::abort();
  return 0;
}
