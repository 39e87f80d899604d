// `hlodr build`: turns a mesh, a glTF scene or a city folder into an HLOD node store.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>

#include "cmd/Commands.h"
#include "hlod/builder/Calibration.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/city/City.h"
#include "hlod/import/Import.h"
#include "hlod/store/NodeStore.h"
#include "hlod/tiles/TilesetImport.h"
#include "service/Args.h"
#include "service/Progress.h"

namespace service::cmd {

const char* const kBuildUsage =
    "usage: hlodr build INPUT... -o NAME.hlod [--level-factor 3] [--desired-tris N]\n"
    "                   [--min-leaf-tris N] [--simplifier meshopt|openmesh|parry] [--c-tex X]\n"
    "                   [--max-block-tri N] [--block-size M] [--threads N]\n"
    "                   [--cells auto|on|off] [--hierarchy auto|planes|objects]\n"
    "                   [--vdr]\n"
    "                   [--lod X] [--up x|y|z] [--quiet]\n"
    "\n"
    "Builds the HLOD node store (Lakhia et al. III-A/B) that `hlodr render` streams from disk.\n"
    "INPUT is a city folder (with city.json; blocks are loaded one at a time), a CityJSON file\n"
    "or mesh files (OBJ, PLY, OFF, STL, glTF/GLB), or an OGC 3D Tiles tileset.json (1.0 or 1.1:\n"
    "its own hierarchy and geometric errors are kept, nothing is simplified again; see\n"
    "docs/3dtiles.md; --up and --c-tex apply, the simplification options do not).\n"
    "Blocks: a city folder's blocks are its own. A CityJSON model's buildings are grouped into\n"
    "blocks by a square grid of --block-size metres over its x/y coordinates (cells at whole\n"
    "multiples of it): each building whole in the cell its footprint centre (the centre of its\n"
    "x-y box) lies in. A mesh file is one block. Each block is then grouped by material\n"
    "(CityJSON: by colour, see docs/cli.md) and cut along its longest axis into pieces of at most\n"
    "--max-block-tri triangles; each piece is one hlod_0 node.\n"
    "Quadtree (Parry et al. sec. 3): each block is anchored at the latitude/longitude of its\n"
    "centre (city folders: the manifest's anchors; CityJSON: through its CRS, geographic,\n"
    "geocentric, RD New (EPSG:28992, 7415) or UTM (EPSG:326zz, 327zz, 258zz)) and inserted\n"
    "into a quadtree over the globe whose smallest cells are about the median block's size;\n"
    "without an anchor (mesh files, other CRSs) the quadtree covers the model's own x/y.\n"
    "Frustum culling starts at its cells. Several city folders or geo-referenced CityJSON\n"
    "files make one store of a region: all placed, through ECEF, in the first input's\n"
    "east-north-up frame, in one quadtree; an input without an anchor cannot join them.\n"
    "Per block: hlod_0 is the block simplified to desiredTri triangles; each level down has\n"
    "levelFactor times more detail, divided into levelFactor pieces perpendicular to the\n"
    "longest dimension (each triangle whole to the piece its centre lies in), down to leaves\n"
    "that hold exactly the original triangles. Vertices a piece shares with its neighbours are\n"
    "locked, so neighbouring nodes meet on the same edges at every level.\n"
    "\n"
    "options:\n"
    "  -o, --output DIR     the store folder to write (written under a temporary name and\n"
    "                       renamed at the end; replaces an earlier store there)\n"
    "  --level-factor N     C_levelFactor, 2..16 (default 3)\n"
    "  --desired-tris N     C_desiredTri, triangles per node, 16..10000000 (default 800;\n"
    "                       --desired-tri is the same option)\n"
    "  --min-leaf-tris N    a piece is divided only when its children would hold N triangles\n"
    "                       on average: leaves hold N..levelFactor*N (default 2000)\n"
    "  --simplifier NAME    meshopt (default, meshoptimizer), openmesh (quadric decimater) or\n"
    "                       parry (Parry et al.: the block's children are its facades, faces\n"
    "                       simplified by sphere-hierarchy vertex clustering with their\n"
    "                       outlines kept; each node can be drawn with any triangle count\n"
    "                       down to its faces' outlines)\n"
    "  --c-tex X            c_tex of the cost (eq. 1), 0..1; default: the value `hlodr\n"
    "                       calibrate` stored ($HLODR_CALIBRATION or\n"
    "                       ~/.config/hlodr/calibration.json), else 0.6\n"
    "  --max-block-tri N    triangles per hlod_0 node's piece of a block, at most\n"
    "                       (default 200000)\n"
    "  --block-size M       CityJSON: the side of the grid cells that group buildings into\n"
    "                       blocks, 1..100000 metres (default 100)\n"
    "  --cells auto|on|off  cell nodes above the blocks: the HLOD of the block quadtree's\n"
    "                       cells, each simplified from the nodes below it, so that far blocks\n"
    "                       cost less than their hlod_0 (default auto: when the blocks' hlod_0\n"
    "                       nodes hold more than 200,000 triangles, what a 33 ms frame draws)\n"
    "  --hierarchy H        planes: the blocks and plane cuts above; objects: the object\n"
    "                       hierarchy of Manocha sec. 2.2 for CAD scenes of many objects (glTF\n"
    "                       nodes, OBJ o/g groups, each mesh file one): large objects split,\n"
    "                       small ones clustered by proximity, an AABB tree over them, HLODs\n"
    "                       bottom up (docs/objects.md); auto (default): objects for a model of\n"
    "                       at least 16 objects that is not a city, planes otherwise\n"
    "  --threads N          blocks built at once, 1..256 (default: one per core); memory grows\n"
    "                       with the blocks in flight, the store is the same for any N\n"
    "  --vdr                also the view-dependent section (vdr.bin; `--selector vdr`): per\n"
    "                       block a vertex hierarchy of edge collapses (virtual edges between\n"
    "                       parts closer than 1% of the block's diagonal), each vertex's local\n"
    "                       Hausdorff error and each collapse's face neighbourhood, cut into a\n"
    "                       cluster hierarchy (Manocha sec. 3, 3.1; docs/vdr.md)\n"
    "  --lod X              CityJSON: the level of detail to import, as the file names it (1, 2,\n"
    "                       2.2 ...); objects without it are left out (default: each city\n"
    "                       object at its highest)\n"
    "  --up x|y|z           the axis the model stands on, stored in the store for camera\n"
    "                       paths and default views (default: z for city folders and\n"
    "                       CityJSON, y for OBJ, glTF/GLB, PLY, OFF and STL)\n"
    "  --quiet              no progress line, no summary\n";

namespace {

std::string formatSeconds(double s) {
  char buf[32];
  if (s >= 60)
    std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
  else
    std::snprintf(buf, sizeof buf, "%.0fs", s);
  return buf;
}

// `hlodr build TILESET.json`: the tileset's tree as the store's (hlod/tiles/TilesetImport.h).
int buildTileset(const std::string& in, const std::string& out, const hlod::BuildOptions& build,
                 bool quiet) {
  hlod::tiles::TilesetImportOptions options;
  options.cTex = build.cTex;
  options.up = build.up;
  ProgressLine lines("build", quiet);
  lines.update(0.0, "reading " + in);
  auto report = hlod::tiles::buildStoreFromTileset(
      in, out, options, [&](const hlod::tiles::TilesetImportProgress& p) {
        lines.update(double(p.tilesDone) / double(std::max<std::size_t>(1, p.tileCount)),
                     std::to_string(p.tilesDone) + "/" + std::to_string(p.tileCount) + " tiles");
      });
  lines.done();
  if (!report) return commandError("build", report.message());
  // Warnings show also with --quiet; a tileset can repeat one per tile, so the first few.
  for (std::size_t i = 0; i < report->warnings.size() && i < 8; ++i)
    std::fprintf(stderr, "warning: %s\n", report->warnings[i].c_str());
  if (report->warnings.size() > 8)
    std::fprintf(stderr, "warning: ... and %zu more\n", report->warnings.size() - 8);
  if (!quiet) {
    std::uint32_t depth = 0;
    for (const auto& n : report->skeleton.nodes) depth = std::max(depth, n.level + 1);
    std::printf(
        "wrote %s: %zu nodes from %zu tiles (%zu content files, %zu without content, %zu refined "
        "by ADD), depth %u, %zu roots, %.2f M triangles, %s up%s\n",
        out.c_str(), report->nodes, report->tiles, report->contents, report->emptyTiles,
        report->addTiles, depth, report->skeleton.roots.size(), double(report->triangles) / 1e6,
        hlod::upAxisName(report->skeleton.up),
        report->hlodrExport ? " (an hlodr export, read back as its store)" : "");
    std::printf("frame: %s\n", report->frame.c_str());
  }
  return 0;
}

}  // namespace

int runBuild(const Argv& argv) {
  auto args = Args::parse(argv, {"quiet", "vdr"},
                          {"output", "level-factor", "desired-tris", "desired-tri", "simplifier",
                           "c-tex", "max-block-tri", "lod", "up", "min-leaf-tris", "threads",
                           "block-size", "cells", "hierarchy"});
  if (!args) {
    std::fprintf(stderr, "hlodr build: %s\n%s", args.message().c_str(), kBuildUsage);
    return 2;
  }
  if (args->positionals().empty()) {
    std::fprintf(stderr, "hlodr build: no input given\n%s", kBuildUsage);
    return 2;
  }
  const auto out = args->get("output");
  if (!out || out->empty()) {
    std::fprintf(stderr, "hlodr build: an output store is required (-o NAME.hlod)\n%s",
                 kBuildUsage);
    return 2;
  }
  const auto levelFactor = args->integer("level-factor", 3, 2, 16);
  const char* desiredTriName = args->has("desired-tri") ? "desired-tri" : "desired-tris";
  const auto desiredTri = args->integer(desiredTriName, hlod::kDefaultDesiredTri, 16, 10000000);
  const auto maxBlock =
      args->integer("max-block-tri", hlod::kDefaultMaxBlockTriangles, 1000, 100000000);
  const auto minLeaf = args->integer("min-leaf-tris", hlod::kDefaultMinLeafTri, 1, 10000000);
  const auto threads = args->integer("threads", 0, 1, 256);
  for (const auto* r : {&levelFactor, &desiredTri, &maxBlock, &minLeaf, &threads})
    if (!*r) {
      std::fprintf(stderr, "hlodr build: %s\n", r->message().c_str());
      return 2;
    }
  hlod::BuildOptions options;
  options.levelFactor = int(*levelFactor);
  options.desiredTri = std::uint32_t(*desiredTri);
  options.minLeafTri = std::uint32_t(*minLeaf);
  options.threads = unsigned(*threads);
  options.maxBlockTriangles = std::size_t(*maxBlock);
  const auto blockSize = args->number("block-size", hlod::kDefaultBlockSize, 1.0, 100000.0);
  if (!blockSize) {
    std::fprintf(stderr, "hlodr build: %s\n", blockSize.message().c_str());
    return 2;
  }
  options.blockSize = *blockSize;
  options.vdr = args->has("vdr");
  options.simplifier = args->get("simplifier", "meshopt");
  if (options.simplifier != "meshopt" && options.simplifier != "openmesh" &&
      options.simplifier != "parry") {
    std::fprintf(stderr, "hlodr build: unknown simplifier '%s' (meshopt, openmesh or parry)\n",
                 options.simplifier.c_str());
    return 2;
  }
  const std::string cells = args->get("cells", "auto");
  if (cells != "auto" && cells != "on" && cells != "off") {
    std::fprintf(stderr, "hlodr build: --cells must be auto, on or off (not '%s')\n",
                 cells.c_str());
    return 2;
  }
  options.cells = cells == "on"    ? hlod::CellMode::On
                  : cells == "off" ? hlod::CellMode::Off
                                   : hlod::CellMode::Auto;
  const std::string hierarchy = args->get("hierarchy", "auto");
  if (hierarchy != "auto" && hierarchy != "planes" && hierarchy != "objects") {
    std::fprintf(stderr, "hlodr build: --hierarchy must be auto, planes or objects (not '%s')\n",
                 hierarchy.c_str());
    return 2;
  }
  options.hierarchy = hierarchy == "planes"    ? hlod::HierarchyMode::Planes
                      : hierarchy == "objects" ? hlod::HierarchyMode::Objects
                                               : hlod::HierarchyMode::Auto;
  if (auto up = args->get("up")) {
    options.up = hlod::parseUpAxis(*up);
    if (!options.up) {
      std::fprintf(stderr, "hlodr build: --up must be x, y or z (not '%s')\n", up->c_str());
      return 2;
    }
  }
  const bool quiet = args->has("quiet");
  std::string cTexSource = "--c-tex";
  if (args->has("c-tex")) {
    const auto c = args->number("c-tex", hlod::kDefaultCTex, 0.0, 1.0);
    if (!c) {
      std::fprintf(stderr, "hlodr build: %s\n", c.message().c_str());
      return 2;
    }
    options.cTex = *c;
  } else if (auto calibrated = hlod::readCalibratedCTex(); !calibrated) {
    std::fprintf(stderr, "hlodr build: %s (fix or remove it, or give --c-tex)\n",
                 calibrated.message().c_str());
    return 2;
  } else if (calibrated->has_value()) {
    options.cTex = **calibrated;
    cTexSource = "calibration file";
  } else {
    options.cTex = hlod::kDefaultCTex;
    cTexSource = "default";
  }

  ProgressLine lines("build", quiet);
  const auto t0 = std::chrono::steady_clock::now();  // import included
  std::uint64_t inputTriangles = 0;
  auto progress = [&](const hlod::BuildProgress& p) {
    inputTriangles = p.trianglesDone;
    const double rate = p.seconds > 0 ? double(p.trianglesDone) / p.seconds : 0.0;
    const double eta =
        p.blocksDone ? p.seconds / double(p.blocksDone) * double(p.blockCount - p.blocksDone) : 0.0;
    char text[160];
    if (p.nodeCount > 0) {
      std::snprintf(text, sizeof text, "object hierarchy: node %zu/%zu", p.nodesDone, p.nodeCount);
      lines.update(double(p.nodesDone) / double(p.nodeCount), text);
      return;
    }
    if (p.cellCount > 0) {
      std::snprintf(text, sizeof text, "cell nodes: quadtree cell %zu/%zu", p.cellsDone,
                    p.cellCount);
      lines.update(double(p.cellsDone) / double(p.cellCount), text);
      return;
    }
    std::snprintf(text, sizeof text, "%zu/%zu blocks, %.2f M input triangles/s, ETA %s",
                  p.blocksDone, p.blockCount, rate / 1e6, formatSeconds(eta).c_str());
    lines.update(p.blockCount ? double(p.blocksDone) / double(p.blockCount) : 1.0, text);
  };

  const auto& inputs = args->positionals();
  // A 3D Tiles tileset keeps its own hierarchy: nothing is simplified again.
  for (const auto& in : inputs)
    if (hlod::tiles::isTilesetFile(in)) {
      if (inputs.size() > 1)
        return usageError("build", in + " is a 3D Tiles tileset: build it on its own");
      return buildTileset(in, *out, options, quiet);
    }
  std::vector<hlod::BuildInput> sources;
  for (const auto& in : inputs) {
    hlod::BuildInput source;
    source.name = in;
    if (hlod::isCityFolder(in)) {
      source.cityDir = in;
      sources.push_back(std::move(source));
      continue;
    }
    if (std::filesystem::is_directory(in)) {
      lines.done();
      std::fprintf(stderr, "hlodr build: %s is a folder without city.json\n", in.c_str());
      return 1;
    }
    lines.update(0.0, "importing " + in);
    hlod::ImportOptions importOptions;
    importOptions.lod = args->get("lod", "");
    auto m = hlod::importModel(in, importOptions);
    if (!m) {
      lines.done();
      std::fprintf(stderr, "hlodr build: %s\n", m.message().c_str());
      return 1;
    }
    if (!m->warnings.empty()) lines.done();
    // Warnings show also with --quiet (which silences progress and the summary only).
    for (const auto& w : m->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    // The store has one up axis: all inputs must agree (city folders are z up).
    const bool firstZUp = sources.empty() || sources.front().cityDir || sources.front().model.zUp;
    if (!sources.empty() && m->zUp != firstZUp && !options.up) {
      lines.done();
      std::fprintf(stderr, "hlodr build: %s is %s-up but %s is %s-up; give --up to choose one\n",
                   in.c_str(), hlod::upAxisName(hlod::upAxisOf(*m)), inputs.front().c_str(),
                   firstZUp ? "z" : "y");
      return 2;
    }
    source.model = std::move(*m);
    sources.push_back(std::move(source));
  }
  // What auto picks, said: a model of many objects (not a city) gets the object hierarchy.
  if (options.hierarchy == hlod::HierarchyMode::Auto) {
    std::size_t objects = 0;
    bool city = false;
    for (const auto& source : sources) {
      city = city || source.cityDir.has_value() || source.model.cityObjects > 0;
      if (!source.cityDir) objects += source.model.objectCount();
    }
    const bool many = !city && objects >= hlod::kManyObjects;
    options.hierarchy = many ? hlod::HierarchyMode::Objects : hlod::HierarchyMode::Planes;
    if (many && !quiet) {
      lines.done();
      std::printf(
          "hierarchy: objects (the input has %zu objects; --hierarchy planes cuts it by "
          "planes instead)\n",
          objects);
      std::fflush(stdout);  // before the progress lines on stderr
    }
  }
  hlod::Result<hlod::Skeleton> built =
      hlod::buildStoreFromInputs(std::move(sources), *out, options, progress);
  lines.done();
  if (!built) {
    std::fprintf(stderr, "hlodr build: %s\n", built.message().c_str());
    return 1;
  }
  if (!quiet) {
    std::uint32_t depth = 0;
    std::size_t cellNodes = 0;
    for (const auto& n : built->nodes) {
      depth = std::max(depth, n.level + 1);
      cellNodes += n.isCell();
    }
    std::printf(
        "wrote %s: %zu nodes from %zu blocks, depth %u, %zu cell nodes (levelFactor %d, "
        "desiredTri %u, %s, c_tex %.3f from %s), %s up\n",
        out->c_str(), built->nodes.size(), built->blockRoots().size(), depth, cellNodes,
        options.levelFactor, options.desiredTri, options.simplifier.c_str(), options.cTex,
        cTexSource.c_str(), hlod::upAxisName(built->up));
    if (options.hierarchy == hlod::HierarchyMode::Objects) {
      std::size_t leaves = 0;
      for (std::uint32_t i = 0; i < built->nodes.size(); ++i) leaves += built->isLeaf(i);
      std::printf("object hierarchy: %zu leaves (redefined objects), %zu HLOD nodes above them\n",
                  leaves, built->nodes.size() - leaves);
    }
    if (options.vdr)
      if (auto store = hlod::NodeStore::open(*out)) {
        std::uint64_t clusters = 0, vertices = 0, bytes = 0;
        for (const hlod::VdrEntry& e : (*store)->vdrEntries())
          clusters += e.clusters, vertices += e.vertices, bytes += e.storedSize;
        std::printf(
            "view-dependent section: %zu objects, %.2f M hierarchy vertices in %llu clusters, "
            "%.1f MB stored\n",
            (*store)->vdrEntries().size(), double(vertices) / 1e6, (unsigned long long)clusters,
            double(bytes) / 1e6);
      }
    const hlod::BlockQuadtree& q = built->quadtree;
    const hlod::QuadtreeStats qs = hlod::quadtreeStats(q);
    std::printf(
        "quadtree: %s, depth %u, %zu cells, %zu blocks in %zu leaf cells (max %zu)\n",
        q.domain == hlod::QuadtreeDomain::Geographic ? "latitude/longitude" : "the model's own x/y",
        q.depth, qs.cells, qs.blocks, qs.leafCells, qs.maxBlocks);
    // ru_maxrss: kilobytes on Linux.
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf(
        "built in %s on %u threads: %.2f M input triangles/s, peak memory %.0f MB\n",
        formatSeconds(seconds).c_str(),
        options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency()),
        seconds > 0 ? double(inputTriangles) / seconds / 1e6 : 0.0,
        double(usage.ru_maxrss) / 1024.0);
  }
  return 0;
}

}  // namespace service::cmd
