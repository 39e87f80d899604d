// `hlodr switch STORE --path PATH.json -o DIR`: the occlusion-switch across three processes
// (service/OcclusionSwitch.h).
#include <cstdio>
#include <string>

#include "cmd/Commands.h"
#include "cmd/SceneArgs.h"
#include "hlod/runtime/CameraPath.h"
#include "hlod/store/NodeStore.h"
#include "service/OcclusionSwitch.h"
#include "service/Progress.h"

namespace service::cmd {

const char* const kSwitchUsage =
    "usage: hlodr switch STORE --path PATH.json -o DIR [options]\n"
    "\n"
    "Runs a camera path through the occlusion-switch of Manocha sec. 4.2-4.5: three processes,\n"
    "each with its own GL context, joined by loopback TCP. Two swap roles every frame: one\n"
    "queries the boxes of the frame's candidate nodes against the depth it drew the frame before\n"
    "(hardware culling, HC), the other draws the visible set it is sent with the next frame's\n"
    "camera (the occluders, OR). The third draws the visible set: the frames, DIR/frame_00000.png\n"
    "... HC sends only the change of the visible set (sec. 4.4); DIR/switch.json gives, per "
    "frame,\n"
    "the candidates, the visible set, the bytes sent and what sending whole sets would take, and\n"
    "the paper's bandwidth formula 8n + nh/b + 3(72 + h) for both (sec. 4.5). The candidates are\n"
    "a fixed-error front (sse or full), the same in every process, and the culling is "
    "conservative:\n"
    "each frame equals the unculled frame of the same front.\n"
    "\n"
    "options:\n"
    "  -o, --output DIR    the folder for the frames and switch.json (required)\n"
    "  --path PATH.json    the camera path, from `hlodr path` (required)\n"
    "  --selector S        the candidates: sse or full (default sse)\n"
    "  --sse-px PX         sse's threshold in pixels: 0.1..1000 (default 16)\n"
    "  --size WxH          frame size in pixels: 16..8192 each side (default 640x360)\n"
    "  --fps N             the path's sampling rate: 0.1..1000 (default 30)\n"
    "  --frames N          only the first N frames of the path (default: all)\n"
    "  --scene FILE        a scene file (docs/scene.md): the effects the frames are drawn with\n"
    "  --unlit, --no-textures, --fog   as for render\n"
    "  --quiet             no progress line, no summary\n";

int runSwitch(const Argv& argv) {
  auto args =
      Args::parse(argv, {"quiet", "unlit", "no-textures", "fog"},
                  {"output", "path", "selector", "sse-px", "size", "fps", "frames", "scene"});
  if (!args) return usageError("switch", args.message() + "\n" + kSwitchUsage);
  if (args->positionals().size() != 1)
    return usageError("switch", std::string("give one node store\n") + kSwitchUsage);
  const std::string out = args->get("output", "");
  if (out.empty()) return usageError("switch", "an output folder is required (-o DIR)");
  if (!args->has("path")) return usageError("switch", "a camera path is required (--path)");
  SwitchOptions o;
  o.selector = args->get("selector", "sse");
  if (o.selector != "sse" && o.selector != "full")
    return usageError("switch", "--selector: sse or full, not '" + o.selector + "'");
  auto px = args->number("sse-px", 16.0, 0.1, 1000.0);
  if (!px) return usageError("switch", px.message());
  o.ssePx = *px;
  auto size = args->size("size", "640x360", 16, 8192);
  if (!size) return usageError("switch", size.message());
  o.width = size->width, o.height = size->height;
  auto fps = args->number("fps", 30.0, 0.1, 1000.0);
  if (!fps) return usageError("switch", fps.message());
  o.fps = *fps;
  auto frames = args->integer("frames", 0, 0, 100000000);
  if (!frames) return usageError("switch", frames.message());
  o.frames = std::uint64_t(*frames);
  const std::string storePath = args->positionals().front();
  auto store = hlod::NodeStore::open(storePath);
  if (!store) return commandError("switch", storePath + ": " + store.message());
  auto declared = sceneFromArgs(*args, hlod::upVector((*store)->skeleton().up));
  if (!declared) return usageError("switch", declared.message());
  o.effects = declared->scene.effects;
  store->reset();
  auto path = hlod::CameraPath::read(args->get("path", ""));
  if (!path) return commandError("switch", args->get("path", "") + ": " + path.message());

  const bool quiet = args->has("quiet");
  ProgressLine lines("switch", quiet);
  auto report = runOcclusionSwitch(storePath, *path, o, out, [&](std::uint64_t d, std::uint64_t t) {
    lines.update(double(d) / double(t), std::to_string(d) + "/" + std::to_string(t) + " frames");
  });
  lines.done();
  if (!report) return commandError("switch", report.message());
  if (!quiet)
    std::printf(
        "wrote %zu frames to %s; HC sent %.0f bytes a frame (whole sets: %.0f, %.0f%% saved); "
        "sec. 4.5's formula: %.0f (whole sets: %.0f)\n",
        report->frames.size(), out.c_str(), report->meanBytes, report->meanFullBytes,
        100.0 * report->savedShare(), report->meanFormulaBytes, report->meanFormulaFullBytes);
  return 0;
}

}  // namespace service::cmd
