#pragma once
// The occlusion-switch across processes (Manocha, "Interactive Display of Complex Environments",
// shared/seeds, sec. 4.2-4.5). Three processes, each with its own GL context (the paper's three
// GPUs in separate PCs), joined by loopback TCP:
//  - A and B form the switch. In frame i one of them does hardware culling (HC): it queries the
//    boxes of frame i's candidate front against the depth it drew in frame i - 1, when it was
//    rendering the occluders (OR) with frame i's camera, and the nodes whose boxes pass are the
//    potential visible set V_i. The other does OR: it draws V_i with frame i + 1's camera, and
//    keeps that depth for its HC in frame i + 1. They swap roles every frame, so the occlusion
//    representation never leaves the GPU that drew it (no depth readback).
//  - RVG draws V_i with frame i's camera: the frame, written as a PNG.
// HC sends each of the others only the change of the visible set with the camera
// (hlod/runtime/VisibleSetDelta.h, sec. 4.4). The candidates are a fixed-error selector's front
// (sse or full: the same in every process without any exchange); frame 0, with no occluders
// yet, draws every candidate. The culling is conservative: the occluders are real geometry of
// frame i's view, so a node with a visible pixel passes its box query and each frame equals the
// unculled frame of the same front (tested). What it costs is latency: frame i is drawn after
// frame i's HC, which waits for frame i - 1's.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "hlod/Result.h"
#include "hlod/runtime/CameraPath.h"
#include "renderer/Renderer.h"

namespace service {

struct SwitchOptions {
  int width = 640;
  int height = 360;
  double fps = 30.0;
  std::uint64_t frames = 0;      // the first N frames of the path; 0: all
  std::string selector = "sse";  // the candidates: sse or full
  double ssePx = 16.0;
  renderer::Effects effects;  // RVG's; OR draws depth only
};

struct SwitchFrame {
  std::uint32_t frame = 0;
  char hc = 'A';                // the process that did HC
  std::size_t candidates = 0;   // the front HC tested
  std::size_t visible = 0;      // |V_i|
  std::size_t added = 0;        // |delta_{i,i-1}|
  std::size_t removed = 0;      // |delta_{i-1,i}|
  std::uint64_t bytes = 0;      // sent by HC this frame: the delta to OR and to RVG
  std::uint64_t fullBytes = 0;  // the same with the whole of V_i in each message
  double hcMs = 0.0, orMs = 0.0, rvgMs = 0.0;
};

struct SwitchReport {
  std::vector<SwitchFrame> frames;
  double meanBytes = 0.0, meanFullBytes = 0.0;
  // Sec. 4.5's 8n + nh/b + 3(72 + h), with this wire format's h and one packet per message
  // (b = n), for n the delta's ids and for n the whole set's: means over the frames.
  double meanFormulaBytes = 0.0, meanFormulaFullBytes = 0.0;
  double savedShare() const { return meanFullBytes > 0.0 ? 1.0 - meanBytes / meanFullBytes : 0.0; }
};

// Runs the path's frames through the three processes (forked from this one, which must not have
// a GL context current) and writes RVG's frames to outDir/frame_00000.png ... and the report to
// outDir/switch.json. progress(done, total) is called as RVG's frames arrive.
hlod::Result<SwitchReport> runOcclusionSwitch(
    const std::string& storePath, const hlod::CameraPath& path, const SwitchOptions& options,
    const std::filesystem::path& outDir,
    const std::function<void(std::uint64_t, std::uint64_t)>& progress = {});

}  // namespace service
