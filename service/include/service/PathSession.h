#pragma once
// One viewing session along a camera path: its GL context, Renderer, the GPU copies of the
// resident nodes (keyed by node id), its selector, its loader thread and its frame statistics.
// Nothing is global, so several sessions can run side by side (one per thread; the context is
// made current on the thread that calls renderFrame).
//
// A frame (Lakhia III-C/D, DESIGN.md "Data flow"):
//   1. drain the loader's events: unloaded nodes free their GPU copy at once; loaded nodes queue
//      for upload;
//   2. upload queued nodes on the render thread under a per-frame upload budget (time and bytes;
//      at least one a frame so uploads always progress); what does not fit waits;
//   3. select the front against what is on the GPU (selector CPU time measured);
//   4. give the load priorities to the loader (and, with prefetch, those of a camera ahead);
//   5. draw; frame time = upload time + the renderer's wall time through glFinish; it goes to the
//      selector's v_time feedback and is the "actual" time of the statistics.
// Realtime mode never waits for the loader (a node whose children are not on the GPU is drawn at
// its own level). Settled mode selects as if everything were resident, waits until that front is
// loaded and uploads it, so frames do not depend on I/O timing (for videos).
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "hlod/CameraPath.h"
#include "hlod/FrameStats.h"
#include "hlod/NodeSource.h"
#include "hlod/Result.h"
#include "hlod/Selector.h"
#include "renderer/GlContext.h"
#include "renderer/Renderer.h"

namespace service {

enum class PathMode { Realtime, Settled };

struct PathSessionOptions {
  int width = 1280;
  int height = 720;
  double budgetMs = 33.0;           // the selector's c_targetTime
  std::string selector = "lakhia";  // "lakhia", "sse", "fs" or "full"
  PathMode mode = PathMode::Realtime;
  std::uint64_t memoryCapBytes = 0;  // loader cap on payload bytes; 0 = none
  double ioMbps = 0.0;               // emulated link; 0 = unthrottled
  double ioLatencyMs = 0.0;
  std::size_t ioRequests = 4;           // requests in flight on the emulated link (LoaderParams)
  double uploadBudgetMs = 2.0;          // per-frame upload time (realtime mode)
  std::uint64_t uploadBudgetBytes = 0;  // per-frame upload bytes; 0 = no byte limit
  double prefetchWeight = 0.5;          // prefetch priorities are scaled by this
  std::chrono::milliseconds settleTimeout{60000};  // settled mode: longest wait for one frame
  renderer::Backend backend = renderer::Backend::Auto;
  renderer::Effects effects;
  hlod::SelectorParams selectorParams;  // c_targetTime is replaced by budgetMs
};

// What renderFrame measured beyond the FrameRecord fields.
struct FrameExtras {
  double queryGpuMs = 0.0;  // the renderer's GL_TIME_ELAPSED sum (GPU time proper)
  double drawMs = 0.0;      // drawFrame wall time through glFinish
  double uploadMs = 0.0;    // uploads done in this frame
  std::uint32_t uploads = 0;
  std::uint64_t uploadBytes = 0;
  std::uint32_t pendingUploads = 0;  // loaded nodes still waiting for an upload
};

class PathSession {
 public:
  // Opens a node store folder (skeleton.bin + payload.bin) and starts a session on it.
  static hlod::Result<std::unique_ptr<PathSession>> open(const std::filesystem::path& store,
                                                         const PathSessionOptions& options);
  // A session on any node source (kept alive by the session). Creates the GL context (current on
  // this thread), loads the hlod_0 nodes and starts the loader thread.
  static hlod::Result<std::unique_ptr<PathSession>> create(
      std::shared_ptr<const hlod::NodeSource> source, const PathSessionOptions& options);
  ~PathSession();
  PathSession(const PathSession&) = delete;
  PathSession& operator=(const PathSession&) = delete;

  // Renders one frame for `sample` (time = path time). lookahead: a camera further along a known
  // path whose selection is given to loader.prefetch (nullptr: none). Appends a FrameRecord.
  hlod::Result<hlod::FrameRecord> renderFrame(const hlod::CameraSample& sample,
                                              const hlod::CameraSample* lookahead = nullptr);
  // The last frame's pixels, RGBA8, row 0 at the top.
  hlod::Image readback();

  const std::vector<hlod::FrameRecord>& frames() const { return frames_; }
  const std::vector<FrameExtras>& extras() const { return extras_; }
  hlod::FrameSummary summary() const { return hlod::summarize(frames_); }
  // stats.json (FrameStats format plus per-frame queryGpuMs, drawMs, uploadMs, uploads,
  // uploadBytes, and the GL description) and stats.csv.
  hlod::Status writeStats(const std::filesystem::path& json,
                          const std::filesystem::path& csv) const;
  // levels.svg, toggles.svg and frametime.svg (Lakhia Figs. 7-9), with `prefix` before each name.
  hlod::Status writePlots(const std::filesystem::path& dir, const std::string& prefix = "") const;

  const hlod::Skeleton& skeleton() const { return source_->skeleton(); }
  const renderer::ContextInfo& contextInfo() const { return context_->info(); }
  const PathSessionOptions& options() const { return options_; }
  const hlod::Selector& selector() const { return *selector_; }
  hlod::LoaderCounters loaderCounters() const;
  std::size_t gpuNodeCount() const;  // nodes with a GPU copy now

 private:
  struct State;
  PathSession() = default;
  hlod::Status init();

  PathSessionOptions options_;
  std::shared_ptr<const hlod::NodeSource> source_;
  std::unique_ptr<renderer::GlContext> context_;
  std::unique_ptr<State> state_;  // renderer, GPU meshes, selectors, loader: die before context_
  std::unique_ptr<hlod::Selector> selector_;
  std::vector<hlod::FrameRecord> frames_;
  std::vector<FrameExtras> extras_;
};

// Runs a whole path through a session and writes its outputs.
struct PathRunOptions {
  // A folder for a PNG sequence (frame_00000.png ...) or a file ending .mp4 (piped to ffmpeg).
  // Empty: no images (stats only, into statsDir).
  std::filesystem::path output;
  std::filesystem::path statsDir;  // only when output is empty
  double fps = 30.0;
  long long maxFrames = -1;      // render only the first N frames; < 0: all
  double prefetchSeconds = 0.0;  // > 0: prefetch the selection this far ahead on the path
  bool plots = false;            // also the three SVG plots
  bool progress = false;         // a progress line on stderr
};

struct PathRunResult {
  hlod::FrameSummary summary;
  std::filesystem::path statsJson, statsCsv;
  std::vector<std::filesystem::path> plots;
  std::size_t framesRendered = 0;
};

hlod::Result<PathRunResult> runPath(PathSession& session, const hlod::CameraPath& path,
                                    const PathRunOptions& options);

}  // namespace service
