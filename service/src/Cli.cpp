#include "service/Cli.h"

#include <cstdio>
#include <cstring>
#include <exception>

#include "cmd/Commands.h"
#include "service/Settings.h"

#ifndef HLODR_VERSION
#define HLODR_VERSION "dev"
#endif

namespace service {

const std::vector<Command>& commands() {
  // One row per subcommand; the usage texts live beside each implementation.
  static const std::vector<Command> table = {
      {"city", "generate the procedural city (the default scene)", cmd::kCityUsage, cmd::runCity},
      {"plant", "generate the procedural power plant (a CAD scene of many objects)",
       cmd::kPlantUsage, cmd::runPlant},
      {"render", "render a frame of a mesh, city folder or node store", cmd::kRenderUsage,
       cmd::runRender},
      {"build", "build an HLOD node store from a mesh, glTF scene or city folder", cmd::kBuildUsage,
       cmd::runBuild},
      {"export-3dtiles", "write a node store as an OGC 3D Tiles 1.1 tileset (glTF per node)",
       cmd::kExport3dTilesUsage, cmd::runExport3dTiles},
      {"info", "show the levels, sizes and build parameters of a node store", cmd::kInfoUsage,
       cmd::runInfo},
      {"calibrate", "measure c_tex (textured vs flat triangle cost) on this GL",
       cmd::kCalibrateUsage, cmd::runCalibrate},
      {"path", "write a camera path (walk-fly, drive, orbit) for a node store", cmd::kPathUsage,
       cmd::runPath},
      {"concat", "join the segments of a split path run (render --segment) into one",
       cmd::kConcatUsage, cmd::runConcat},
      {"study", "what accuracy costs in time: selectors and budgets against full detail",
       cmd::kStudyUsage, cmd::runStudy},
      {"study-build", "the simplifiers per level: distance to the original, triangles, time",
       cmd::kStudyBuildUsage, cmd::runStudyBuild},
      {"switch", "a camera path through the occlusion-switch: three processes, visible-set deltas",
       cmd::kSwitchUsage, cmd::runSwitch},
      {"serve", "serve the HTTP API and the web page over a folder of node stores",
       cmd::kServeUsage, cmd::runServe},
  };
  return table;
}

static void printHelp() {
  std::printf("hlodr %s: headless HLOD rendering of huge models\n\nusage: hlodr COMMAND [ARGS]\n\n",
              HLODR_VERSION);
  for (const auto& c : commands()) std::printf("  %-14s %s\n", c.name, c.summary);
  std::printf(
      "\n`hlodr help COMMAND` or `hlodr COMMAND --help` shows a command's options;\n"
      "`hlodr help settings` every setting's range, default and meaning.\n");
}

int runCli(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    printHelp();
    return argc < 2 ? 2 : 0;
  }
  if (!std::strcmp(argv[1], "--version")) {
    std::printf("hlodr %s\n", HLODR_VERSION);
    return 0;
  }
  std::string name = argv[1];
  std::vector<std::string> args(argv + 2, argv + argc);
  if (name == "help") {
    if (args.empty()) {
      printHelp();
      return 0;
    }
    if (args[0] == "settings") {
      const bool markdown = args.size() > 1 && args[1] == "--markdown";
      const std::string which = args.size() > 2 ? args[2] : "all";
      std::printf("%s", markdown ? settingsMarkdown(which).c_str() : settingsText().c_str());
      return 0;
    }
    name = args[0];
    args = {"--help"};
  }
  for (const auto& c : commands()) {
    if (name != c.name) continue;
    for (const auto& a : args) {
      if (a == "--help" || a == "-h") {
        std::printf("%s", expandUsage(c.usage).c_str());
        return 0;
      }
    }
    try {
      return c.run(args);
    } catch (const std::exception& e) {
      // Bad data never throws by design; this catches resource exhaustion and bugs.
      std::fprintf(stderr, "hlodr %s: internal error: %s\n", c.name, e.what());
      return 1;
    }
  }
  std::fprintf(stderr, "hlodr: unknown command '%s' (see `hlodr help`)\n", name.c_str());
  return 2;
}

}  // namespace service
