// `hlodr study-build MODEL`: the simplifiers compared level by level (hlod/study/BuildStudy.h).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cmd/Commands.h"
#include "hlod/city/City.h"
#include "hlod/import/Import.h"
#include "hlod/study/BuildStudy.h"
#include "service/Args.h"
#include "service/Progress.h"

namespace service::cmd {

const char* const kStudyBuildUsage =
    "usage: hlodr study-build MODEL [-o DIR] [options]\n"
    "\n"
    "Compares the simplifiers level by level. MODEL is a city folder (with city.json) or a mesh\n"
    "file, cut into blocks as `hlodr build` does. Each block's hierarchy is built in memory with\n"
    "each simplifier, and per level the surface of the cut at that level (its nodes and the\n"
    "leaves above it) is measured against the block's original triangles: symmetric Hausdorff\n"
    "and RMS distance sampled on both surfaces, triangles, the builder's own error estimate,\n"
    "simplified triangles facing away from the original surface (holes under back-face\n"
    "culling) and those standing off it farther than their node's error (shards); and the\n"
    "build time. Prints a table; with -o writes DIR/build-study.json and build-study.csv.\n"
    "With --hierarchy objects or both, a mesh file's object hierarchy (Manocha sec. 2.2, as\n"
    "`hlodr build --hierarchy objects` makes it; docs/objects.md) is built too, with each\n"
    "simplifier, and its levels measured the same way against the whole model.\n"
    "\n"
    "options:\n"
    "  -o, --output DIR     folder for the JSON and CSV (created)\n"
    "  --simplifiers LIST   meshopt, openmesh (default both)\n"
    "  --level-factor N     as `hlodr build` (default 3)\n"
    "  --desired-tris N     as `hlodr build` (default 800)\n"
    "  --max-block-tri N    as `hlodr build`, for mesh files (default 200000)\n"
    "  --blocks N           study only the first N blocks (default all)\n"
    "  --samples N          surface samples per block and level on each surface (default 20000)\n"
    "  --hierarchy H        planes (default), objects or both\n"
    "  --min-leaf-tris N    as `hlodr build` (default 2000)\n"
    "  --quiet              no progress line\n";

namespace {

void printTable(const std::vector<hlod::study::SimplifierFigures>& figures) {
  std::printf("%-8s %-9s %5s %6s %10s %11s %11s %11s %9s %8s %8s %10s\n", "hierarchy", "simplif.",
              "level", "nodes", "triangles", "hausdorff", "rms", "error est.", "flipped", "off",
              "build s", "max off");
  for (const auto& f : figures)
    for (const auto& L : f.levels)
      std::printf("%-8s %-9s %5d %6zu %10zu %11.4g %11.4g %11.4g %9zu %8zu %8.2f %10.4g\n",
                  f.hierarchy.c_str(), f.simplifier.c_str(), L.level, L.nodes, L.triangles,
                  L.hausdorff, L.rms, L.geometricError, L.flipped, L.standingOff, f.buildSeconds,
                  L.maxOff);
}

hlod::Status writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) return hlod::makeError("cannot write " + path.string());
  return hlod::Ok{};
}

}  // namespace

int runStudyBuild(const Argv& argv) {
  auto args = Args::parse(argv, {"quiet"},
                          {"output", "simplifiers", "level-factor", "desired-tris", "max-block-tri",
                           "blocks", "samples", "hierarchy", "min-leaf-tris"});
  if (!args) return commandError("study-build", args.message() + "\n" + kStudyBuildUsage, 2);
  if (args->positionals().size() != 1)
    return commandError(
        "study-build",
        std::string("give one MODEL (a city folder or a mesh file)\n") + kStudyBuildUsage, 2);
  const auto levelFactor = args->integer("level-factor", 3, 2, 16);
  const auto desiredTri = args->integer("desired-tris", hlod::kDefaultDesiredTri, 16, 10000000);
  const auto maxBlock =
      args->integer("max-block-tri", hlod::kDefaultMaxBlockTriangles, 1000, 100000000);
  const auto blockLimit = args->integer("blocks", 0, 0, 100000000);
  const auto samples = args->integer("samples", 20000, 100, 10000000);
  const auto minLeaf = args->integer("min-leaf-tris", hlod::kDefaultMinLeafTri, 1, 10000000);
  for (const auto* r : {&levelFactor, &desiredTri, &maxBlock, &blockLimit, &samples, &minLeaf})
    if (!*r) return commandError("study-build", r->message(), 2);
  const std::string hierarchy = args->get("hierarchy", "planes");
  if (hierarchy != "planes" && hierarchy != "objects" && hierarchy != "both")
    return commandError("study-build",
                        "--hierarchy must be planes, objects or both (not '" + hierarchy + "')", 2);
  hlod::study::BuildStudyOptions o;
  o.build.levelFactor = int(*levelFactor);
  o.build.desiredTri = std::uint32_t(*desiredTri);
  o.build.maxBlockTriangles = std::size_t(*maxBlock);
  o.build.minLeafTri = std::uint32_t(*minLeaf);
  o.samplesPerBlock = std::size_t(*samples);
  o.simplifiers.clear();
  std::istringstream names(args->get("simplifiers", "meshopt,openmesh"));
  for (std::string name; std::getline(names, name, ',');) o.simplifiers.push_back(name);
  auto study = hlod::study::BuildStudy::create(o);
  if (!study) return commandError("study-build", study.message(), 2);

  const std::string input = args->positionals()[0];
  ProgressLine lines("study-build", args->has("quiet"));
  std::size_t done = 0;
  auto add = [&](const std::vector<hlod::Block>& blocks, std::size_t total) -> hlod::Status {
    for (const hlod::Block& b : blocks)
      if (auto s = study->addBlock(b); !s) return s;
    ++done;
    lines.update(double(done) / double(total),
                 std::to_string(done) + "/" + std::to_string(total) + " blocks");
    return hlod::Ok{};
  };
  if (hierarchy != "planes" && hlod::isCityFolder(input))
    return commandError("study-build", "a city folder is cut by planes only (--hierarchy planes)",
                        2);
  if (hlod::isCityFolder(input)) {
    auto manifest = hlod::readCityManifest(input);
    if (!manifest) return commandError("study-build", manifest.message());
    std::size_t n = manifest->blocks.size();
    if (*blockLimit > 0) n = std::min<std::size_t>(n, std::size_t(*blockLimit));
    for (std::size_t i = 0; i < n; ++i) {
      auto block = hlod::loadCityBlock(*manifest, i);
      if (!block) return commandError("study-build", block.message());
      hlod::Model one;
      one.meshes.push_back(std::move(*block));
      if (auto s = add(hlod::cutIntoBlocks(one, o.build.maxBlockTriangles), n); !s)
        return commandError("study-build", s.message());
    }
  } else {
    auto model = hlod::importModel(input);
    if (!model) return commandError("study-build", model.message());
    for (const auto& w : model->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (hierarchy != "objects") {
      std::vector<hlod::Block> blocks = hlod::cutIntoBlocks(*model, o.build.maxBlockTriangles);
      if (*blockLimit > 0 && blocks.size() > std::size_t(*blockLimit)) blocks.resize(*blockLimit);
      if (blocks.empty()) return commandError("study-build", input + " has no triangles");
      for (const hlod::Block& b : blocks)
        if (auto s = add({b}, blocks.size()); !s) return commandError("study-build", s.message());
    }
    if (hierarchy != "planes") {
      lines.update(1.0, "the object hierarchy");
      // Its stores go beside the output (or into the temporary folder), removed after.
      const std::filesystem::path scratch = args->has("output")
                                                ? std::filesystem::path(args->get("output", ""))
                                                : std::filesystem::temp_directory_path();
      std::error_code ec;
      std::filesystem::create_directories(scratch, ec);
      if (auto s = study->addObjectModel(*model, scratch); !s)
        return commandError("study-build", s.message());
    }
  }
  lines.done();
  printTable(study->figures());
  if (auto out = args->get("output")) {
    std::error_code ec;
    std::filesystem::create_directories(*out, ec);
    if (ec) return commandError("study-build", "cannot create " + *out + ": " + ec.message());
    const std::filesystem::path dir(*out);
    for (auto [name, text] :
         {std::pair{"build-study.json", hlod::study::buildStudyJson(study->figures())},
          std::pair{"build-study.csv", hlod::study::buildStudyCsv(study->figures())}})
      if (auto s = writeText(dir / name, text); !s) return commandError("study-build", s.message());
  }
  return 0;
}

}  // namespace service::cmd
