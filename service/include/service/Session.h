#pragma once
// One viewing session: its selector state (v_time, hysteresis, last front), its loader thread
// and its GPU residency, driven by a hlod::FrameDriver. Nothing of it is global, so many
// sessions run side by side: in the server, the sessions of one render worker share that
// worker's GL context (each with its own framebuffer and GPU copies); on the command line a
// session makes a context of its own. Sessions of one store may share one decoded CPU node
// cache (SessionOptions::cache).
//
// A session is used on one thread at a time, with its context current (the server's render
// worker; the CLI's main thread); the destructor too.
#include <chrono>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <memory>
#include <string>

#include "hlod/Result.h"
#include "hlod/runtime/CameraPath.h"
#include "hlod/runtime/FrameDriver.h"
#include "hlod/runtime/FrameStats.h"
#include "hlod/runtime/Loader.h"
#include "hlod/runtime/NodeCache.h"
#include "hlod/runtime/PathRun.h"
#include "hlod/runtime/Selector.h"
#include "hlod/store/NodeSource.h"
#include "hlod/vdr/VdrRuntime.h"
#include "renderer/GlContext.h"
#include "renderer/GpuNodeRenderer.h"
#include "renderer/Renderer.h"
#include "renderer/VdrNodeRenderer.h"

namespace service {

struct SessionOptions {
  int width = 1280;
  int height = 720;
  double budgetMs = 33.0;            // the selector's c_targetTime
  std::string selector = "lakhia";   // "lakhia", "sse", "fs", "full" or "vdr"
  std::uint64_t memoryCapBytes = 0;  // loader cap on decoded payload bytes; 0 = none
  double ioMbps = 0.0;               // emulated link; 0 = unthrottled
  double ioLatencyMs = 0.0;
  std::size_t ioRequests = 4;           // requests in flight on the emulated link (LoaderParams)
  double uploadBudgetMs = 2.0;          // per-frame upload time (realtime frames)
  std::uint64_t uploadBudgetBytes = 0;  // per-frame upload bytes; 0 = no byte limit
  double prefetchWeight = 0.5;          // prefetch priorities are scaled by this
  std::chrono::milliseconds settleTimeout{60000};  // settled frames: longest wait for one
  renderer::Effects effects;
  hlod::SelectorParams selectorParams;     // c_targetTime is replaced by budgetMs
  std::shared_ptr<hlod::NodeCache> cache;  // shared with the other sessions of the server
  std::uint32_t cacheStore = 0;            // the store's number in the cache
  double knownVTime = 0.0;                 // > 0: start from this v_time instead of measuring one
  double knownFixedMs = 0.0;               // and this fixed cost (FrameDriver::fixedMs)
  std::size_t recentFrames = 600;          // FrameRecords kept for recent() (a bounded ring)
  hlod::OcclusionMode occlusion = hlod::OcclusionMode::Auto;  // occlusion culling
  std::uint64_t gpuBudgetBytes = 0;  // GPU memory budget (GpuMemoryManager); 0 = none
  bool showOcclusion = false;        // debug view: the occluded nodes' boxes tinted
  bool renderWhileLoading = true;    // settled frames drawn while their front loads
  bool predict = false;              // realtime frames without a path prefetch a predicted camera
  // "vdr": the GPU memory the clusters' arrays may hold over frames (0: no budget), and the
  // share of a cluster's vertices that must be active for it to be drawn from its vertex array
  // (renderer::VdrNodeRenderer).
  std::uint64_t vdrGpuBudgetBytes = 0;
  double vdrMinActiveRatio = 0.25;
};

class Session {
 public:
  // A session on `context`, which must be current on this thread now and whenever the session
  // is used; the context must outlive the session.
  static hlod::Result<std::unique_ptr<Session>> create(
      std::shared_ptr<const hlod::NodeSource> source, const SessionOptions& options,
      renderer::GlContext& context);
  // A session on a GL context of its own (made current on this thread).
  static hlod::Result<std::unique_ptr<Session>> create(
      std::shared_ptr<const hlod::NodeSource> source, const SessionOptions& options,
      renderer::Backend backend = renderer::Backend::Auto);
  // Opens a node store folder (skeleton.bin + payload.bin), on a context of its own.
  static hlod::Result<std::unique_ptr<Session>> open(
      const std::filesystem::path& store, const SessionOptions& options,
      renderer::Backend backend = renderer::Backend::Auto);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // One frame (see hlod::FrameDriver::renderFrame); the record is also kept in recent().
  hlod::Result<hlod::FrameRecord> renderFrame(const hlod::CameraSample& sample,
                                              hlod::FrameMode mode,
                                              const hlod::CameraSample* lookahead = nullptr);
  // The last frame's pixels, RGBA8, row 0 at the top.
  hlod::Image readback();
  // The last frame's geometry coverage (from depth, exact whatever the background).
  hlod::metrics::Mask coverage();

  hlod::FrameDriver& driver() { return *driver_; }
  // The GL renderer that draws the front (with "vdr", the one under the cluster renderer).
  renderer::GpuNodeRenderer& gpu() { return vdrRenderer_ ? vdrRenderer_->inner() : *renderer_; }
  const renderer::GpuNodeRenderer& gpu() const {
    return vdrRenderer_ ? vdrRenderer_->inner() : *renderer_;
  }
  const hlod::Selector& selector() const { return driver_->selector(); }
  // The skeleton the front's nodes belong to: the store's, or with "vdr" the clusters'.
  const hlod::Skeleton& skeleton() const { return driver_->selector().skeleton(); }
  const renderer::ContextInfo& contextInfo() const { return context_->info(); }
  renderer::GlContext& context() { return *context_; }
  const SessionOptions& options() const { return options_; }
  hlod::LoaderCounters loaderCounters() const { return loader_->counters(); }
  std::string lastLoadError() const { return loader_->lastError(); }
  // Empty while every node loaded; else what a command says and fails with: a node that failed
  // to load was drawn coarser, so the frames show a damaged store, not the model.
  std::string loadFailure() const;
  std::size_t gpuNodeCount() const { return gpu().residency().size(); }
  std::uint64_t gpuBytes() const { return gpu().residency().gpuBytes(); }
  // The last recentFrames records, oldest first.
  const std::deque<hlod::FrameRecord>& recent() const { return driver_->recent(); }
  hlod::FrameSummary recentSummary() const;
  // The session's settings and GL as a JSON object (merged into stats.json as "session").
  std::string settingsJson() const;

 private:
  Session() = default;
  hlod::Status init(renderer::GlContext& context);
  // The selector and the GPU side of "vdr" (view-dependent rendering of the store's section).
  hlod::Status initVdr(const renderer::RenderOptions& ro, const hlod::SelectorParams& sp,
                       std::unique_ptr<hlod::Selector>& selector);

  SessionOptions options_;
  std::shared_ptr<const hlod::NodeSource> source_;
  std::unique_ptr<renderer::GlContext> ownContext_;  // when not given one; dies last
  renderer::GlContext* context_ = nullptr;
  std::unique_ptr<hlod::vdr::VdrRuntime> vdr_;              // "vdr": the objects' fronts
  std::unique_ptr<renderer::GpuNodeRenderer> renderer_;     // GL objects: die with context current
  std::unique_ptr<renderer::VdrNodeRenderer> vdrRenderer_;  // "vdr": instead of renderer_
  std::unique_ptr<hlod::Loader> loader_;
  std::unique_ptr<hlod::FrameDriver> driver_;
};

const char* modeName(hlod::FrameMode mode);
// "realtime" or "settled"; anything else is an Error.
hlod::Result<hlod::FrameMode> parseMode(const std::string& name);

// A path run into files, as `hlodr render STORE --path` writes them.
struct FileOutputs {
  // A folder for a PNG sequence (frame_00000.png ...), or a file ending .mp4 (ffmpeg). Empty: no
  // images, stats only (into statsDir).
  std::filesystem::path output;
  std::filesystem::path statsDir;
  bool plots = false;  // the three SVG figures of Lakhia IV too
  // Not empty: the run's per-frame timing as Chrome Trace Event JSON (service/ChromeTrace.h).
  std::filesystem::path trace;
};

struct FileRunResult {
  hlod::PathRunResult run;
  hlod::FrameSummary summary;
  std::filesystem::path statsJson, statsCsv;
  std::vector<std::filesystem::path> plots;
};

hlod::Result<FileRunResult> runPathToFiles(Session& session, const hlod::CameraPath& path,
                                           const hlod::PathRunOptions& run,
                                           const FileOutputs& outputs,
                                           const hlod::FrameCallback& onFrame = {},
                                           const std::atomic<bool>* cancel = nullptr);

}  // namespace service
