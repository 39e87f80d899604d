// `hlodr plant`: writes the procedural power plant (a CAD scene of many objects) as a GLB.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "cmd/Commands.h"
#include "hlod/plant/PowerPlant.h"
#include "service/Args.h"

namespace service::cmd {

const char* const kPlantUsage =
    "usage: hlodr plant -o DIR [--objects N] [--seed S] [--detail X] [--quiet]\n"
    "\n"
    "Writes a procedural power plant, the kind of CAD scene Manocha's paper renders (the Power\n"
    "Plant: 13 M polygons in 1,200 objects; the Double Eagle tanker: 82 M in 127 k), to\n"
    "DIR/plant.glb: a glTF 2.0 binary any viewer opens. Units of a boiler in a steel frame with\n"
    "three levels of walkways, railings and a stair tower, a tank yard and branch pipes; pipe\n"
    "racks with a catwalk at 7 m joined to the units; long pipe runs snaking over every rack\n"
    "(bends, flanges every 12 m), valves, bolts on every flange, pipe shoes. Objects are glTF\n"
    "nodes grouped by function (structure, equipment, piping, valves, fasteners, access);\n"
    "repeated parts are instanced meshes. Flat materials, one per part type. Metres, Y up.\n"
    "`hlodr build DIR/plant.glb` builds it with the object hierarchy (--hierarchy auto);\n"
    "`hlodr path STORE --kind catwalk` walks its catwalks (docs/objects.md).\n"
    "\n"
    "options:\n"
    "  -o, --output DIR  folder to write (created if missing)\n"
    "  --objects N       about how many objects, 1..1000000 (default 20000: about 10 units,\n"
    "                    10 M triangles; 100000 gives about 50 units and 50 M triangles);\n"
    "                    at least one unit, about 2,000 objects\n"
    "  --seed S          random seed, 0..9223372036854775807 (default 1); the same options\n"
    "                    give a byte-identical file\n"
    "  --detail X        tessellation, 0.1..4 (default 1: 64 sides a pipe): triangles grow\n"
    "                    about as its square\n"
    "  --quiet           no summary\n";

int runPlant(const Argv& argv) {
  auto args = Args::parse(argv, {"quiet"}, {"output", "objects", "seed", "detail"});
  if (!args) return usageError("plant", args.message() + "\n" + kPlantUsage);
  if (!args->positionals().empty())
    return usageError("plant", "unexpected argument '" + args->positionals().front() + "'");
  const auto dir = args->get("output");
  if (!dir || dir->empty()) return usageError("plant", "an output folder is required (-o DIR)");
  const auto objects =
      args->integer("objects", 20000, hlod::kMinPlantObjects, hlod::kMaxPlantObjects);
  const auto seed = args->integer("seed", 1, 0, 9223372036854775807LL);
  const auto detail = args->number("detail", 1.0, 0.1, 4.0);
  for (const auto* r : {&objects, &seed})
    if (!*r) return usageError("plant", r->message());
  if (!detail) return usageError("plant", detail.message());
  hlod::PlantOptions options;
  options.objects = std::uint64_t(*objects);
  options.seed = std::uint64_t(*seed);
  options.detail = *detail;
  const auto t0 = std::chrono::steady_clock::now();
  std::error_code ec;
  std::filesystem::create_directories(*dir, ec);
  if (ec) return commandError("plant", *dir + ": cannot create the folder (" + ec.message() + ")");
  const hlod::Plant plant = hlod::makePowerPlant(options);
  const std::filesystem::path file = std::filesystem::path(*dir) / "plant.glb";
  if (auto s = hlod::writeGlb(plant.scene, file); !s) return commandError("plant", s.message());
  if (args->has("quiet")) return 0;
  const hlod::PlantSummary& p = plant.summary;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "wrote %s: %llu objects, %.2f M triangles (%zu units, %zu racks, %zu long pipe "
      "runs) in %.1f s, %.1f MB\n",
      file.c_str(), (unsigned long long)p.objects, double(p.triangles) / 1e6, p.units, p.racks,
      p.pipeRuns, seconds, double(std::filesystem::file_size(file, ec)) / 1e6);
  const glm::dvec3 size = p.bounds.size();
  std::printf("site %.0f x %.0f m, %.0f m high\n", size.x, size.z, size.y);
  std::printf("  %-12s %9s %12s\n", "part", "objects", "triangles");
  for (const auto& [type, n] : p.byType)
    std::printf("  %-12s %9llu %12llu\n", type.c_str(), (unsigned long long)n.first,
                (unsigned long long)n.second);
  return 0;
}

}  // namespace service::cmd
