// `hlodr city`: writes the procedural city (hlodr's default scene) to a folder.
#include <cstdio>
#include <string>

#include "cmd/Commands.h"
#include "hlod/city/City.h"
#include "service/Args.h"
#include "service/Progress.h"

namespace service::cmd {

const char* const kCityUsage =
    "usage: hlodr city -o DIR [--blocks N] [--seed S] [--texture PX] [--quiet]\n"
    "\n"
    "Writes the procedural city, hlodr's default scene, modelled on the scanned city blocks of\n"
    "Lakhia et al.: each block is one side of a city block, a row of building facades (window\n"
    "recesses, ledges, cornices, rooftop units, sidewalk) with its own texture.\n"
    "\n"
    "Output: DIR/city.json (block list with triangle counts, bounds, lat/lon anchors) and per\n"
    "block DIR/block_NNNN.ply (binary PLY, double positions, normals, texture coordinates) and\n"
    "DIR/block_NNNN.png (RGBA texture atlas, PX x PX).\n"
    "Frame: metres, X east, Y north, Z up; origin at lat 37.87, lon -122.27. Four blocks per\n"
    "street-grid cell, cells filling a square from the origin.\n"
    "\n"
    "options:\n"
    "  -o, --output DIR  folder to write (created if missing)\n"
    "  --blocks N        number of blocks, 1..100000 (default 64: about 2.5 million\n"
    "                    triangles; triangles grow linearly, ~39k a block, so 600 blocks\n"
    "                    give about 23 million)\n"
    "  --seed S          random seed, 0..9223372036854775807 (default 1); the same seed\n"
    "                    gives byte-identical files\n"
    "  --texture PX      texture size of a block, 64..4096 (default 512, ~7 texels a metre);\n"
    "                    painting and PNG encoding are most of the time: 1024 is ~3x slower\n"
    "  --quiet           no progress line, no summary\n";

int runCity(const Argv& argv) {
  auto args = Args::parse(argv, {"quiet"}, {"output", "blocks", "seed", "texture"});
  if (!args) {
    std::fprintf(stderr, "hlodr city: %s\n%s", args.message().c_str(), kCityUsage);
    return 2;
  }
  if (!args->positionals().empty()) {
    std::fprintf(stderr, "hlodr city: unexpected argument '%s'\n%s",
                 args->positionals().front().c_str(), kCityUsage);
    return 2;
  }
  const auto dir = args->get("output");
  if (!dir || dir->empty()) {
    std::fprintf(stderr, "hlodr city: an output folder is required (-o DIR)\n%s", kCityUsage);
    return 2;
  }
  const auto blocks = args->integer("blocks", hlod::kDefaultCityBlocks, 1, hlod::kMaxCityBlocks);
  const auto seed = args->integer("seed", static_cast<long long>(hlod::kDefaultCitySeed), 0,
                                  9223372036854775807LL);
  const auto texture = args->integer("texture", hlod::kDefaultCityTextureSize, 64, 4096);
  for (const auto* r : {&blocks, &seed, &texture})
    if (!*r) {
      std::fprintf(stderr, "hlodr city: %s\n", r->message().c_str());
      return 2;
    }

  hlod::CityOptions options;
  options.blocks = static_cast<int>(*blocks);
  options.seed = static_cast<std::uint64_t>(*seed);
  options.textureSize = static_cast<int>(*texture);
  const bool quiet = args->has("quiet");
  ProgressLine lines("city", quiet);

  double seconds = 0.0;
  std::size_t triangles = 0;
  auto progress = [&](const hlod::CityProgress& p) {
    seconds = p.seconds;
    triangles = p.triangles;
    const double rate = p.seconds > 0 ? p.triangles / p.seconds : 0.0;
    char text[160];
    std::snprintf(text, sizeof text, "%d/%d blocks, %.2f M triangles, %.2f M triangles/s",
                  p.blocksDone, p.blocksTotal, p.triangles / 1e6, rate / 1e6);
    lines.update(double(p.blocksDone) / p.blocksTotal, text);
  };
  const hlod::Status status = hlod::writeCity(*dir, options, progress);
  lines.done();
  if (!status) {
    std::fprintf(stderr, "hlodr city: %s\n", status.message().c_str());
    return 1;
  }
  if (!quiet)
    std::printf("wrote %d blocks, %zu triangles to %s in %.2f s (%.2f M triangles/s)\n",
                options.blocks, triangles, dir->c_str(), seconds,
                seconds > 0 ? triangles / seconds / 1e6 : 0.0);
  return 0;
}

}  // namespace service::cmd
