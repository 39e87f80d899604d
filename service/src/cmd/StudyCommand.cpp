// `hlodr study STORE --path PATH.json -o DIR`: what accuracy costs in time (service/Study.h).
#include <cstdio>
#include <sstream>

#include "cmd/Commands.h"
#include "cmd/SceneArgs.h"
#include "hlod/store/NodeStore.h"
#include "service/Args.h"
#include "service/Progress.h"
#include "service/Study.h"

namespace service::cmd {

const char* const kStudyUsage =
    "usage: hlodr study STORE (--path PATH.json | --kind walk-fly|drive|orbit|facade) -o DIR "
    "[options]\n"
    "\n"
    "The accuracy study: for frames spread over the camera path, the full-detail reference and\n"
    "each selector at each budget (SSE at each pixel threshold), with frame time (wall through\n"
    "glFinish, and GPU query time), triangles, PSNR, SSIM and FLIP against the reference, the\n"
    "coverage difference (holes, shards), the front's screen-space error, toggles and bytes\n"
    "loaded. Writes DIR/study.json, study.csv, pareto.svg, flip.svg, path.svg, db-per-ms.svg,\n"
    "strip-N.png and index.html (open it in a browser, offline).\n"
    "\n"
    "options:\n"
    "  --budgets LIST      frame budgets in ms (default 8,16,33,66,133)\n"
    "  --selectors LIST    lakhia, sse, fs, vdr (default lakhia,sse,fs; vdr needs a store\n"
    "                      built with --vdr)\n"
    "  --sse-px LIST       SSE thresholds in pixels (default 1,2,4,8,16,32)\n"
    "  --size WxH          frame size (default 640x360)\n"
    "  --frames N          frames studied, spread evenly over the path (default 24)\n"
    "  --fps N             the path's frame rate (default 30; realtime runs every frame)\n"
    "  --mode M            settled (default), realtime or both\n"
    "  --strips N          frames shown in strips at every Lakhia budget (default 3)\n"
    "  --memory-mb N       loader memory cap per session (default: none)\n"
    "  --params N=V,...    selector constants of the studied runs, as for `hlodr render`\n"
    "                      (splats=1, progressive=0 ...); the reference uses the defaults\n"
    "  --splats on|off     as `--params splats=1|0`\n"
    "  --scene FILE        the effects every frame draws (docs/scene.md; default: textures,\n"
    "                      lambert shading and the sun, as `hlodr render`); or --unlit,\n"
    "                      --no-textures, --fog\n"
    "  --quiet             no progress line\n";

namespace {

hlod::Result<std::vector<double>> numberList(const std::string& s, double lo, double hi,
                                             const char* name) {
  std::vector<double> out;
  std::istringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi)
      return hlod::makeError(std::string("--") + name + ": '" + item + "' is not a number in " +
                             std::to_string(lo).substr(0, 6) + ".." +
                             std::to_string(hi).substr(0, 8));
    out.push_back(v);
  }
  if (out.empty()) return hlod::makeError(std::string("--") + name + " is empty");
  return out;
}

}  // namespace

int runStudy(const Argv& argv) {
  auto args =
      Args::parse(argv, {"quiet", "unlit", "no-textures", "fog"},
                  {"output", "path", "kind", "budgets", "selectors", "sse-px", "size", "frames",
                   "fps", "mode", "strips", "memory-mb", "scene", "params", "splats"});
  if (!args) return commandError("study", args.message() + "\n" + kStudyUsage, 2);
  if (args->positionals().size() != 1)
    return commandError(
        "study", std::string("give one node STORE (made by `hlodr build`)\n") + kStudyUsage, 2);
  if (!args->has("output"))
    return commandError("study", std::string("-o DIR is required\n") + kStudyUsage, 2);
  if (args->has("path") == args->has("kind"))
    return commandError(
        "study", "give the camera path: --path PATH.json or --kind walk-fly|drive|orbit|facade", 2);
  StudyOptions o;
  auto budgets = numberList(args->get("budgets", "8,16,33,66,133"), 0.5, 10000, "budgets");
  auto sse = numberList(args->get("sse-px", "1,2,4,8,16,32"), 0.05, 10000, "sse-px");
  if (!budgets) return commandError("study", budgets.message(), 2);
  if (!sse) return commandError("study", sse.message(), 2);
  o.budgets = *budgets;
  o.ssePx = *sse;
  o.selectors.clear();
  std::istringstream sels(args->get("selectors", "lakhia,sse,fs"));
  for (std::string s; std::getline(sels, s, ',');) {
    if (s != "lakhia" && s != "sse" && s != "fs" && s != "vdr")
      return commandError("study", "--selectors: '" + s + "' is not one of lakhia, sse, fs, vdr",
                          2);
    o.selectors.push_back(s);
  }
  auto size = args->size("size", "640x360", 16, 4096);
  if (!size) return commandError("study", size.message(), 2);
  o.width = size->width;
  o.height = size->height;
  auto frames = args->integer("frames", 24, 1, 100000);
  auto fps = args->number("fps", 30.0, 1.0, 240.0);
  auto strips = args->integer("strips", 3, 0, 20);
  auto memory = args->number("memory-mb", 0.0, 0.0, 1e7);
  if (!frames) return commandError("study", frames.message(), 2);
  if (!fps) return commandError("study", fps.message(), 2);
  if (!strips) return commandError("study", strips.message(), 2);
  if (!memory) return commandError("study", memory.message(), 2);
  o.frames = std::size_t(*frames);
  o.fps = *fps;
  o.stripFrames = std::size_t(*strips);
  o.memoryCapBytes = std::uint64_t(*memory * 1048576.0);
  if (auto p = hlod::setSelectorParams(o.selectorParams, args->get("params", "")); !p)
    return commandError("study", "--params: " + p.message(), 2);
  auto splats = args->onOff("splats", o.selectorParams.splats);
  if (!splats) return commandError("study", splats.message(), 2);
  o.selectorParams.splats = *splats;
  const std::string mode = args->get("mode", "settled");
  if (mode != "settled" && mode != "realtime" && mode != "both")
    return commandError("study", "--mode must be settled, realtime or both", 2);
  o.settled = mode != "realtime";
  o.realtime = mode != "settled";
  // Stores do not keep the model's up axis yet: the study's paths are Z-up.
  auto declared = sceneFromArgs(*args, {0.0, 0.0, 1.0});
  if (!declared) return commandError("study", declared.message(), 2);
  o.effects = declared->scene.effects;

  const std::string storePath = args->positionals()[0];
  if (!isNodeStore(storePath))
    return commandError("study",
                        storePath +
                            " is not a node store (a folder with skeleton.bin; make one with "
                            "`hlodr build`)");
  auto store = hlod::NodeStore::open(storePath);
  if (!store) return commandError("study", storePath + ": " + store.message());
  std::shared_ptr<const hlod::NodeStore> source(std::move(*store));
  auto path = args->has("path") ? hlod::CameraPath::read(args->get("path", ""))
                                : hlod::makeCameraPath(args->get("kind", ""), source->skeleton());
  if (!path) return commandError("study", "the camera path: " + path.message());

  nlohmann::json settings = {
      {"store", storePath},
      {"path", args->has("path") ? args->get("path", "") : "kind " + args->get("kind", "")},
      {"size", std::to_string(o.width) + "x" + std::to_string(o.height)},
      {"frames", o.frames},
      {"fps", o.fps},
      {"mode", mode},
      {"budgets", o.budgets},
      {"selectors", o.selectors},
      {"ssePx", o.ssePx},
      {"params", args->get("params", "")},
      {"splats", o.selectorParams.splats},
      {"scene", declared->fromFile ? declared->file.string() : std::string("default effects")}};
  ProgressLine progress("study", args->has("quiet"));
  auto report = service::runStudy(
      source, *path, o, args->get("output", ""), settings,
      [&](const std::string& what, double fraction) { progress.update(fraction, what); });
  progress.done();
  if (!report) return commandError("study", report.message());
  for (const auto& line : hlod::study::answer(report->runs).lines())
    std::printf("%s\n", line.c_str());
  std::printf("report: %s/index.html\n", args->get("output", "").c_str());
  return 0;
}

}  // namespace service::cmd
