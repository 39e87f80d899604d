#pragma once
// Declarations of the subcommands listed in Cli.cpp. One file per command in this folder.
#include <array>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "service/Args.h"

namespace service::cmd {

using Argv = std::vector<std::string>;

// "hlodr CMD: MESSAGE" on stderr; returns code (1: failed, 2: bad usage).
inline int commandError(const char* cmd, const std::string& message, int code = 1) {
  std::fprintf(stderr, "hlodr %s: %s\n", cmd, message.c_str());
  return code;
}
inline int usageError(const char* cmd, const std::string& message) {
  return commandError(cmd, message, 2);
}

extern const char* const kCityUsage;
int runCity(const Argv& args);

extern const char* const kPlantUsage;
int runPlant(const Argv& args);

extern const char* const kRenderUsage;
int runRender(const Argv& args);

extern const char* const kBuildUsage;
int runBuild(const Argv& args);

extern const char* const kExport3dTilesUsage;
int runExport3dTiles(const Argv& args);

extern const char* const kInfoUsage;
int runInfo(const Argv& args);

extern const char* const kCalibrateUsage;
int runCalibrate(const Argv& args);

extern const char* const kStudyUsage;
int runStudy(const Argv& args);

extern const char* const kStudyBuildUsage;
int runStudyBuild(const Argv& args);

extern const char* const kSwitchUsage;
int runSwitch(const Argv& args);

extern const char* const kServeUsage;
int runServe(const Argv& args);

extern const char* const kConcatUsage;
int runConcat(const Argv& args);

extern const char* const kPathUsage;
int runPath(const Argv& args);
// `hlodr render STORE --path PATH.json`: a camera path through a Session (PathCommand.cpp).
int runRenderPath(const Argv& args);
// `hlodr render STORE [--camera ...] -o IMAGE`: one budget-bound frame (RenderStoreCommand.cpp).
int runRenderStoreFrame(const Argv& args);
// --camera PX,PY,PZ,TX,TY,TZ: six finite numbers, the position apart from the target; the
// message says which value is wrong (RenderCommand.cpp).
hlod::Result<std::array<double, 6>> parseCamera(const std::string& s);
bool isNodeStore(const std::string& path);
// The options and flags only a camera path run takes (both render forms parse them, so that a
// single-frame render can say they need a node store and --path).
extern const std::set<std::string> kPathRunOptions;
extern const std::set<std::string> kPathRunFlags;
// Args::parse with the path-run options and flags added to the form's own.
hlod::Result<Args> parseWithPathRun(const Argv& argv, std::set<std::string> flags,
                                    std::set<std::string> options);

}  // namespace service::cmd
