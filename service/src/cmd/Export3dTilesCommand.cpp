// `hlodr export-3dtiles`: a node store as an OGC 3D Tiles 1.1 tileset (hlod/tiles/TilesetExport.h).
#include <cstdio>
#include <string>

#include "cmd/Commands.h"
#include "hlod/tiles/TilesetExport.h"
#include "service/Args.h"
#include "service/Progress.h"

namespace service::cmd {

const char* const kExport3dTilesUsage =
    "usage: hlodr export-3dtiles STORE -o DIR [--jpeg QUALITY] [--quiet]\n"
    "\n"
    "Writes the node store as an OGC 3D Tiles 1.1 tileset that CesiumJS, cesium-native and\n"
    "3DTilesRendererJS stream: DIR/tileset.json and one binary glTF per node (DIR/content/).\n"
    "The tiles are the store's nodes (refine REPLACE); each tile's geometricError is its node's\n"
    "simplification error, so that a viewer at 16 px screen-space error refines where\n"
    "`--selector sse` at 16 px does (leaves 0). Boxes hold every vertex. A geo-referenced store\n"
    "(a city folder, a CityJSON with a geographic, geocentric, RD New or UTM CRS) is placed on\n"
    "the globe by a root transform from its east-north-up frame to ECEF; each tile's positions\n"
    "are relative to its centre. Textures shared by several nodes are written once.\n"
    "`hlodr build DIR/tileset.json -o STORE` reads the export back as the store it came from.\n"
    "Progressions (--simplifier parry) are not exported: each tile holds its node's triangles.\n"
    "\n"
    "options:\n"
    "  -o, --output DIR    the folder to write (replaces an earlier export there, nothing else)\n"
    "  --jpeg QUALITY      textures as JPEG of quality 1..100 (default: PNG, lossless)\n"
    "  --quiet             no progress line, no summary\n";

int runExport3dTiles(const Argv& argv) {
  auto args = Args::parse(argv, {"quiet"}, {"output", "jpeg"});
  if (!args) return usageError("export-3dtiles", args.message() + "\n" + kExport3dTilesUsage);
  if (args->positionals().size() != 1)
    return usageError("export-3dtiles", std::string("give one node store\n") + kExport3dTilesUsage);
  const auto out = args->get("output");
  if (!out || out->empty())
    return usageError("export-3dtiles",
                      std::string("an output folder is required (-o DIR)\n") + kExport3dTilesUsage);
  hlod::tiles::TilesetExportOptions options;
  if (args->has("jpeg")) {
    const auto q = args->integer("jpeg", 90, 1, 100);
    if (!q) return usageError("export-3dtiles", q.message());
    options.jpegQuality = int(*q);
  }
  const std::string& storePath = args->positionals().front();
  auto store = hlod::NodeStore::open(storePath);
  if (!store) return commandError("export-3dtiles", store.message());
  const bool quiet = args->has("quiet");
  ProgressLine lines("export-3dtiles", quiet);
  auto report =
      hlod::tiles::exportTileset(**store, *out, options, [&](std::size_t done, std::size_t total) {
        lines.update(double(done) / double(total),
                     std::to_string(done) + "/" + std::to_string(total) + " nodes");
      });
  lines.done();
  if (!report) return commandError("export-3dtiles", report.message());
  if (!quiet)
    std::printf("wrote %s: %zu tiles, %zu glTF contents, %zu shared textures, %.1f MB; %s\n",
                out->c_str(), report->tiles, report->contents, report->sharedTextures,
                double(report->bytes) / 1e6, report->frame.c_str());
  return 0;
}

}  // namespace service::cmd
