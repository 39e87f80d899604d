// `hlodr info`: what a node store holds, per level; or what a model file imports as.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "cmd/Commands.h"
#include "cmd/HierarchyInfo.h"
#include "cmd/VdrInfo.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/geodesy/GeoReference.h"
#include "hlod/import/Import.h"
#include "hlod/store/NodeStore.h"
#include "service/Args.h"

namespace service::cmd {

const char* const kInfoUsage =
    "usage: hlodr info STORE [--json]\n"
    "       hlodr info MODEL [--lod X] [--block-size M] [--json]\n"
    "\n"
    "Prints a node store's build parameters, up axis, coordinate reference system, block count,\n"
    "depth, payload bytes, the triangles per node (min, p10, median, p90, max over the leaves and\n"
    "over all nodes), the leaf triangles against the input's, nodes and triangles per level, and\n"
    "the block quadtree: over latitude/longitude or, for a model without a geographic anchor,\n"
    "over its own x/y; its depth, cells, the smallest cell's size (degrees and about metres),\n"
    "blocks per leaf cell (max, mean) and the blocks' latitude/longitude extent.\n"
    "Checks the skeleton (checksum, tree structure, model frame) on the way.\n"
    "For a model file (mesh, glTF, CityJSON) prints what `hlodr build` would import: format and\n"
    "version, coordinate reference system, city objects, the LoD chosen, meshes, triangles, and\n"
    "the extent in the model's units (for data converted to east-north-up metres, the origin),\n"
    "and for CityJSON the blocks `hlodr build` would make and where they are anchored.\n"
    "Both print the hierarchy's figures for the criteria of Manocha sec. 2.1.1 (localisation,\n"
    "depth and balance, sibling-box overlap, object sizes; docs/objects.md): a store's tree, or\n"
    "for a model its object hierarchy beside its plane cuts, as `hlodr build` makes them.\n"
    "A store built with --vdr also gets its view-dependent section's cluster hierarchy (Manocha\n"
    "sec. 3.1): clusters per depth with their error ratios and error ranges (Yoon et al. 2003;\n"
    "--json lists every cluster's).\n"
    "\n"
    "options:\n"
    "  --json          machine-readable output\n"
    "  --lod X         CityJSON: the level of detail to import (default: each object at its\n"
    "                  highest)\n"
    "  --block-size M  CityJSON: the block grid's side in metres, as for `hlodr build`\n"
    "                  (default 100)\n";

namespace {

// The simplifier name is bytes from the file: escape what is not printable ASCII, so that
// terminal escape codes do not reach the terminal and the JSON stays valid UTF-8.
std::string printable(const std::string& name) {
  std::string out;
  for (const unsigned char c : name) {
    if (c >= 0x20 && c < 0x7f && c != '\\') {
      out += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
  }
  return out;
}

std::string formatOf(const std::filesystem::path& path, const hlod::Model& model) {
  if (!model.format.empty()) return model.format;
  std::string ext = path.extension().string();
  for (char& c : ext) c = char(std::toupper(static_cast<unsigned char>(c)));
  return ext.empty() ? "mesh" : ext.substr(1);
}

// Min, p10, median, p90 and max of a list of triangle counts (nearest rank; zeros when empty).
struct Spread {
  std::uint32_t min = 0, p10 = 0, median = 0, p90 = 0, max = 0;
};

Spread spreadOf(std::vector<std::uint32_t> v) {
  Spread s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) { return v[std::size_t(q * double(v.size() - 1) + 0.5)]; };
  s.min = v.front();
  s.p10 = at(0.1);
  s.median = at(0.5);
  s.p90 = at(0.9);
  s.max = v.back();
  return s;
}

nlohmann::json toJson(const Spread& s) {
  return {{"min", s.min}, {"p10", s.p10}, {"median", s.median}, {"p90", s.p90}, {"max", s.max}};
}

std::string describe(const Spread& s) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "min %u, p10 %u, median %u, p90 %u, max %u", s.min, s.p10,
                s.median, s.p90, s.max);
  return buf;
}

int modelInfo(const std::string& file, const Args& args) {
  hlod::ImportOptions options;
  options.lod = args.get("lod", "");
  const auto start = std::chrono::steady_clock::now();
  auto model = hlod::importModel(file, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!model) {
    std::fprintf(stderr, "hlodr info: %s\n", model.message().c_str());
    return 1;
  }
  for (const auto& w : model->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  const hlod::Aabb b = model->bounds();
  const glm::dvec3 size = b.size();
  const hlod::ModelCrs& crs = model->crs;
  const std::string format = formatOf(file, *model);
  // The blocks `hlodr build` would make: grid blocks of buildings, each cut by colour and size.
  const auto blockSize = args.number("block-size", hlod::kDefaultBlockSize, 1.0, 100000.0);
  if (!blockSize) {
    std::fprintf(stderr, "hlodr info: %s\n", blockSize.message().c_str());
    return 2;
  }
  std::size_t blocks = 0, roots = 0;
  if (model->cityObjects > 0) {
    for (const auto& block : hlod::groupBuildingsIntoBlocks(*model, *blockSize)) {
      ++blocks;
      roots += hlod::cutIntoBlocks(block.model, hlod::kDefaultMaxBlockTriangles).size();
    }
  }
  const hlod::GeoReference geo = hlod::GeoReference::of(crs);
  const std::string anchors = geo.known()
                                  ? "latitude/longitude through " + geo.describe()
                                  : std::string("none (the quadtree covers the model's own x/y)");
  if (args.has("json")) {
    nlohmann::json j;
    j["model"] = file;
    j["format"] = format;
    j["meshes"] = model->meshes.size();
    j["triangles"] = model->triangleCount();
    j["importSeconds"] = seconds;
    j["bounds"] = {{"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}};
    j["extent"] = {size.x, size.y, size.z};
    j["up"] = model->zUp ? "z" : "y";
    if (!model->format.empty()) {
      j["crs"] = {{"epsg", crs.epsg}, {"description", crs.description}, {"toEnu", crs.toEnu}};
      if (crs.toEnu)
        j["crs"]["origin"] = {
            {"lat", crs.originLat}, {"lon", crs.originLon}, {"height", crs.originHeight}};
      j["cityObjects"] = model->cityObjects;
      j["lod"] = model->lod;
      j["blockSize"] = *blockSize;
      j["blocks"] = blocks;
      j["blockRoots"] = roots;
      j["anchors"] = anchors;
    }
    j["objects"] = model->objectCount();
    j["hierarchy"] = modelHierarchyInfo(*model, false);
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("model         %s\n", file.c_str());
  std::printf("format        %s\n", printable(format).c_str());
  if (!model->format.empty()) {
    std::printf("CRS           %s\n", crs.description.c_str());
    if (crs.toEnu)
      std::printf("ENU origin    lat %.9f, lon %.9f, height %.3f m (WGS 84)\n", crs.originLat,
                  crs.originLon, crs.originHeight);
    std::printf("city objects  %zu\n", model->cityObjects);
    std::printf("LoD           %s\n", printable(model->lod).c_str());
    std::printf("blocks        %zu of %g m (%zu hlod_0 nodes after the split by colour)\n", blocks,
                *blockSize, roots);
    std::printf("anchors       %s\n", anchors.c_str());
  }
  std::printf("meshes        %zu\n", model->meshes.size());
  for (const auto& m : model->meshes)
    std::printf("  %-28s %9zu triangles, colour %.2f %.2f %.2f%s\n", printable(m.name).c_str(),
                m.triangleCount(), m.baseColor.r, m.baseColor.g, m.baseColor.b,
                m.oneSided ? ", one-sided" : "");
  std::printf("triangles     %zu (imported in %.2f s)\n", model->triangleCount(), seconds);
  const char* units = crs.toEnu ? " m (east, north, up)" : " (the model's units)";
  std::printf("extent        %.3f x %.3f x %.3f%s\n", size.x, size.y, size.z, units);
  std::printf("bounds        (%.3f, %.3f, %.3f) .. (%.3f, %.3f, %.3f)\n", b.min.x, b.min.y, b.min.z,
              b.max.x, b.max.y, b.max.z);
  std::printf("objects       %zu\n", model->objectCount());
  modelHierarchyInfo(*model, true);
  return 0;
}

}  // namespace

int runInfo(const Argv& argv) {
  auto args = Args::parse(argv, {"json"}, {"lod", "block-size"});
  if (!args) {
    std::fprintf(stderr, "hlodr info: %s\n%s", args.message().c_str(), kInfoUsage);
    return 2;
  }
  if (args->positionals().size() != 1) {
    std::fprintf(stderr, "hlodr info: give exactly one store or model file\n%s", kInfoUsage);
    return 2;
  }
  if (!isNodeStore(args->positionals()[0])) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(args->positionals()[0], ec))
      return modelInfo(args->positionals()[0], *args);
  }
  auto store = hlod::NodeStore::open(args->positionals()[0]);
  if (!store) {
    std::fprintf(stderr, "hlodr info: %s\n", store.message().c_str());
    return 1;
  }
  const hlod::Skeleton& s = (*store)->skeleton();
  const hlod::StoreFacts& f = (*store)->facts();
  struct Level {
    std::size_t nodes = 0, leaves = 0;
    std::uint64_t triangles = 0, payloadBytes = 0, memoryBytes = 0;
    std::uint64_t textureStored = 0, textureBytes = 0;  // of the above, the textures'
    std::uint64_t fewest = 0, splats = 0;  // Parry: triangles at the coarsest progression
  };
  std::map<std::uint32_t, Level> levels;
  Level cells;  // cell nodes (Skeleton.h), above the blocks' levels
  std::set<std::uint64_t> textureSections;
  std::uint64_t leafTriangles = 0;
  std::vector<std::uint32_t> leafTris, nodeTris;
  for (std::uint32_t i = 0; i < s.nodes.size(); ++i) {
    const auto& n = s.nodes[i];
    nodeTris.push_back(n.numTri);
    if (s.isLeaf(i)) leafTris.push_back(n.numTri);
    auto& l = n.isCell() ? cells : levels[n.level];
    ++l.nodes;
    l.triangles += n.numTri;
    l.fewest += n.progressive() ? n.minTri : n.numTri;
    l.splats += n.splatCount;
    // A texture section shared by several nodes of a level is stored (and, by a loader,
    // held) once: count it once.
    l.payloadBytes += n.meshSize();
    l.memoryBytes += n.memoryBytes - n.textureBytes;
    if (n.textureSize > 0 && textureSections.insert(n.textureOffset).second) {
      l.payloadBytes += n.textureSize;
      l.memoryBytes += n.textureBytes;
      l.textureStored += n.textureSize;
      l.textureBytes += n.textureBytes;
    }
    if (s.isLeaf(i)) {
      ++l.leaves;
      leafTriangles += n.numTri;
    }
  }
  const std::size_t depth = levels.size();
  const Spread leafSpread = spreadOf(std::move(leafTris)),
               nodeSpread = spreadOf(std::move(nodeTris));
  // The leaves hold the input's triangles, less those the build dropped (degenerate, welded).
  const double leafRatio =
      f.inputTriangles > 0 ? double(leafTriangles) / double(f.inputTriangles) : 0.0;
  // The decoder let only printable ASCII through; printable() keeps that promise here too.
  const std::string crsText = printable(s.crs.description);
  const hlod::BlockQuadtree& q = s.quadtree;
  const hlod::QuadtreeStats qs = hlod::quadtreeStats(q);
  const bool geographic = q.domain == hlod::QuadtreeDomain::Geographic;
  const char* domain = geographic  ? "latitude/longitude (the globe at the root)"
                       : q.empty() ? "none"
                                   : "the model's own x/y (no geographic anchor)";
  if (args->has("json")) {
    nlohmann::json j;
    j["store"] = args->positionals()[0];
    j["formatVersion"] = hlod::kSkeletonFormatVersion;
    j["params"] = {{"levelFactor", s.params.levelFactor},
                   {"desiredTri", s.params.desiredTri},
                   {"cTex", s.params.cTex},
                   {"simplifier", printable(s.params.simplifier)}};
    j["nodes"] = s.nodes.size();
    j["blocks"] = f.blockCount;
    j["depth"] = depth;
    j["up"] = hlod::upAxisName(s.up);
    j["crs"] = {{"epsg", s.crs.epsg}, {"description", crsText}, {"toEnu", s.crs.toEnu}};
    if (s.crs.toEnu)
      j["crs"]["origin"] = {
          {"lat", s.crs.originLat}, {"lon", s.crs.originLon}, {"height", s.crs.originHeight}};
    j["quadtree"] = {{"domain", geographic  ? "geographic"
                                : q.empty() ? "none"
                                            : "model"},
                     {"depth", q.depth},
                     {"cells", qs.cells},
                     {"leafCells", qs.leafCells},
                     {"blocks", qs.blocks},
                     {"leafSize", {qs.leafSize.x, qs.leafSize.y}},
                     {"blocksPerLeaf", {{"max", qs.maxBlocks}, {"mean", qs.meanBlocks}}},
                     {"rootsPerLeaf", {{"max", qs.maxRoots}, {"mean", qs.meanRoots}}}};
    if (geographic) {
      j["quadtree"]["leafMetres"] = {qs.leafMetres.x, qs.leafMetres.y};
      j["quadtree"]["extent"] = {{"minLat", qs.anchors.minV},
                                 {"maxLat", qs.anchors.maxV},
                                 {"minLon", qs.anchors.minU},
                                 {"maxLon", qs.anchors.maxU}};
    }
    j["inputTriangles"] = f.inputTriangles;
    j["leafTriangles"] = leafTriangles;
    j["leafToInputTriangles"] = leafRatio;
    j["trianglesPerNode"] = {{"leaves", toJson(leafSpread)}, {"allNodes", toJson(nodeSpread)}};
    j["payloadBytes"] = f.payloadBytes;
    j["buildSeconds"] = f.buildSeconds;
    const auto levelJson = [](const Level& l) {
      return nlohmann::json{{"nodes", l.nodes},
                            {"leaves", l.leaves},
                            {"triangles", l.triangles},
                            {"payloadBytes", l.payloadBytes},
                            {"memoryBytes", l.memoryBytes},
                            {"texturePayloadBytes", l.textureStored},
                            {"textureMemoryBytes", l.textureBytes},
                            {"fewestTriangles", l.fewest},
                            {"splats", l.splats}};
    };
    j["cells"] = levelJson(cells);
    j["levels"] = nlohmann::json::array();
    for (const auto& [d, l] : levels) {
      nlohmann::json level = levelJson(l);
      level["level"] = d;
      j["levels"].push_back(level);
    }
    j["hierarchy"] = storeHierarchyInfo(s, false);
    auto vdr = vdrInfo(**store, false);
    if (!vdr) {
      std::fprintf(stderr, "hlodr info: %s\n", vdr.message().c_str());
      return 1;
    }
    j["vdr"] = std::move(*vdr);
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("store         %s\n", args->positionals()[0].c_str());
  std::printf("built with    levelFactor %g, desiredTri %u, c_tex %.3f, simplifier %s (%.1f s)\n",
              s.params.levelFactor, s.params.desiredTri, s.params.cTex,
              printable(s.params.simplifier).c_str(), f.buildSeconds);
  std::printf("up axis       %s\n", hlod::upAxisName(s.up));
  std::printf("CRS           %s\n", crsText.empty() ? "none" : crsText.c_str());
  if (s.crs.toEnu)
    std::printf("ENU origin    lat %.9f, lon %.9f, height %.3f m (WGS 84)\n", s.crs.originLat,
                s.crs.originLon, s.crs.originHeight);
  std::printf("blocks        %u\n", f.blockCount);
  std::printf("quadtree      %s, depth %u, %zu cells, %zu leaf cells\n", domain, q.depth, qs.cells,
              qs.leafCells);
  if (geographic)
    std::printf("smallest cell %.6f x %.6f degrees (lon x lat), about %.0f x %.0f m\n",
                qs.leafSize.x, qs.leafSize.y, qs.leafMetres.x, qs.leafMetres.y);
  else if (!q.empty())
    std::printf("smallest cell %.3f x %.3f (the model's units)\n", qs.leafSize.x, qs.leafSize.y);
  if (!q.empty())
    std::printf("blocks/cell   max %zu, mean %.2f (hlod_0 nodes: max %zu, mean %.2f)\n",
                qs.maxBlocks, qs.meanBlocks, qs.maxRoots, qs.meanRoots);
  if (geographic)
    std::printf("lat/lon       %.6f .. %.6f, %.6f .. %.6f (%zu block anchors)\n", qs.anchors.minV,
                qs.anchors.maxV, qs.anchors.minU, qs.anchors.maxU, qs.blocks);
  std::printf("nodes         %zu\n", s.nodes.size());
  std::printf("depth         %zu\n", depth);
  std::printf("triangles     %llu input, %llu at the leaves\n",
              (unsigned long long)f.inputTriangles, (unsigned long long)leafTriangles);
  std::printf("leaf / input  %.4f\n", leafRatio);
  std::printf("tris/node     leaves: %s\n", describe(leafSpread).c_str());
  std::printf("              all nodes: %s\n", describe(nodeSpread).c_str());
  Level all = cells;
  for (const auto& [d, l] : levels) {
    all.memoryBytes += l.memoryBytes;
    all.textureStored += l.textureStored;
    all.textureBytes += l.textureBytes;
  }
  std::printf(
      "payload       %.2f MB stored (deflated; %.2f MB of it textures), %.2f MB decoded"
      " (%.2f MB textures)\n",
      double(f.payloadBytes) / 1e6, double(all.textureStored) / 1e6, double(all.memoryBytes) / 1e6,
      double(all.textureBytes) / 1e6);
  // "fewest": the triangles of the level with every progression at its coarsest (Parry's arrays;
  // the same as triangles without them).
  std::printf(
      "\n  level     nodes    leaves     triangles   stored MB  decoded MB  texture MB"
      "       fewest     splats\n");
  const auto row = [](const std::string& name, const Level& l) {
    std::printf("  %5s  %8zu  %8zu  %12llu  %10.2f  %10.2f  %10.2f  %11llu  %9llu\n", name.c_str(),
                l.nodes, l.leaves, (unsigned long long)l.triangles, double(l.payloadBytes) / 1e6,
                double(l.memoryBytes) / 1e6, double(l.textureBytes) / 1e6,
                (unsigned long long)l.fewest, (unsigned long long)l.splats);
  };
  if (cells.nodes > 0) row("cells", cells);
  for (const auto& [d, l] : levels) row(std::to_string(d), l);
  storeHierarchyInfo(s, true);
  if (auto vdr = vdrInfo(**store, true); !vdr) {
    std::fprintf(stderr, "hlodr info: %s\n", vdr.message().c_str());
    return 1;
  }
  return 0;
}

}  // namespace service::cmd
