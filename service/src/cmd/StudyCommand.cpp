// `hlodr study STORE --path PATH.json -o DIR`: what accuracy costs in time (service/Study.h).
#include <cstdio>
#include <sstream>

#include "cmd/Commands.h"
#include "cmd/SceneArgs.h"
#include "hlod/store/NodeStore.h"
#include "service/Args.h"
#include "service/Progress.h"
#include "service/Settings.h"
#include "service/Study.h"

namespace service::cmd {

const char* const kStudyUsage =
    "usage: hlodr study STORE (--path PATH.json | --kind KIND) -o DIR [options]\n"
    "\n"
    "The accuracy study: for frames spread over the camera path, the full-detail reference and\n"
    "each selector at each budget (SSE at each pixel threshold), with frame time (wall through\n"
    "glFinish, and GPU query time), triangles, PSNR, SSIM and FLIP against the reference, the\n"
    "coverage difference (holes, shards), the front's screen-space error, toggles and bytes\n"
    "loaded. Writes DIR/study.json, study.csv, pareto.svg, flip.svg, path.svg, db-per-ms.svg,\n"
    "strip-N.png and index.html (open it in a browser, offline).\n"
    "\n"
    "KIND: a generated path, as `hlodr path --kind` makes it (walk-fly, drive, orbit, facade,\n"
    "fly-around, catwalk).\n"
    "\n"
    "options:\n"
    "{study.budgets}\n"
    "{study.selectors}\n"
    "{study.ssePx}\n"
    "{study.size}\n"
    "{study.frames}\n"
    "{fps}\n"
    "{study.mode}\n"
    "{study.strips}\n"
    "{memoryMb}\n"
    "{occlusion}\n"
    "{study.referenceMb}\n"
    "  --params N=V,...        selector constants of the studied runs, as for `hlodr render`\n"
    "                          (splats=1, progressive=0 ...); the reference uses the defaults\n"
    "{splats}\n"
    "  --scene FILE            the effects every frame draws (docs/scene.md; default: textures,\n"
    "                          lambert shading and the sun, as `hlodr render`); or --unlit,\n"
    "                          --no-textures, --fog\n"
    "  --trace FILE            every run's frames as Chrome Trace Event JSON (Perfetto UI,\n"
    "                          chrome://tracing), a process per run (the reference is not\n"
    "                          traced)\n"
    "  --quiet                 no progress line\n";

int runStudy(const Argv& argv) {
  auto args = Args::parse(
      argv, {"quiet", "unlit", "no-textures", "fog"},
      {"output", "path", "kind", "budgets", "selectors", "sse-px", "size", "frames", "fps", "mode",
       "strips", "memory-mb", "scene", "params", "splats", "occlusion", "reference-mb", "trace"});
  if (!args) return commandError("study", args.message() + "\n" + expandUsage(kStudyUsage), 2);
  if (args->positionals().size() != 1)
    return commandError(
        "study", "give one node STORE (made by `hlodr build`)\n" + expandUsage(kStudyUsage), 2);
  if (!args->has("output"))
    return commandError("study", "-o DIR is required\n" + expandUsage(kStudyUsage), 2);
  if (args->has("path") == args->has("kind"))
    return commandError("study", "give the camera path: --path PATH.json or --kind KIND", 2);
  using settings::get;
  StudyOptions o;
  auto budgets = args->numbers(get("study.budgets"));
  auto sse = args->numbers(get("study.ssePx"));
  auto selectors = args->choices(get("study.selectors"));
  if (!budgets) return commandError("study", budgets.message(), 2);
  if (!sse) return commandError("study", sse.message(), 2);
  if (!selectors) return commandError("study", selectors.message(), 2);
  o.budgets = *budgets;
  o.ssePx = *sse;
  o.selectors = *selectors;
  auto size = args->size(get("study.size"));
  if (!size) return commandError("study", size.message(), 2);
  o.width = size->width;
  o.height = size->height;
  auto frames = args->integer(get("study.frames"));
  auto fps = args->number(get("fps"));
  auto strips = args->integer(get("study.strips"));
  auto memory = args->number(get("memoryMb"));
  auto referenceMemory = args->number(get("study.referenceMb"));
  if (!frames) return commandError("study", frames.message(), 2);
  if (!fps) return commandError("study", fps.message(), 2);
  if (!strips) return commandError("study", strips.message(), 2);
  if (!memory) return commandError("study", memory.message(), 2);
  if (!referenceMemory) return commandError("study", referenceMemory.message(), 2);
  o.frames = std::size_t(*frames);
  o.fps = *fps;
  o.stripFrames = std::size_t(*strips);
  o.memoryCapBytes = std::uint64_t(*memory * 1048576.0);
  o.referenceCapBytes = std::uint64_t(*referenceMemory * 1048576.0);
  if (auto p = hlod::setSelectorParams(o.selectorParams, args->get("params", "")); !p)
    return commandError("study", "--params: " + p.message(), 2);
  auto splats = args->choice(get("splats"));
  if (!splats) return commandError("study", splats.message(), 2);
  if (args->has("splats")) o.selectorParams.splats = *splats == "on";
  auto occlusion = args->choice(get("occlusion"));
  if (!occlusion) return commandError("study", occlusion.message(), 2);
  o.occlusion = *hlod::parseOcclusionMode(*occlusion);  // the table's choices parse
  auto studyMode = args->choice(get("study.mode"));
  if (!studyMode) return commandError("study", studyMode.message(), 2);
  const std::string mode = *studyMode;
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
                                : hlod::makeCameraPath(args->get("kind", ""), *source);
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
      {"occlusion", *occlusion},
      {"scene", declared->fromFile ? declared->file.string() : std::string("default effects")}};
  o.trace = args->get("trace", "");
  ProgressLine progress("study", args->has("quiet"));
  auto report = service::runStudy(
      source, *path, o, args->get("output", ""), settings,
      [&](const std::string& what, double fraction) { progress.update(fraction, what); });
  progress.done();
  if (!report) return commandError("study", report.message());
  for (const auto& line : hlod::study::answer(report->runs).lines())
    std::printf("%s\n", line.c_str());
  std::printf("report: %s/index.html\n", args->get("output", "").c_str());
  if (!o.trace.empty()) std::printf("trace: %s\n", o.trace.string().c_str());
  return 0;
}

}  // namespace service::cmd
