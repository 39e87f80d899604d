// A viewing session: a FrameDriver with its loader, selectors and GPU side on a GL context.
#include "service/Session.h"

#include <cctype>
#include <cmath>

#include <nlohmann/json.hpp>

#include "hlod/runtime/Framing.h"
#include "hlod/runtime/VdrSelector.h"
#include "hlod/scene/SceneFile.h"
#include "hlod/store/NodeStore.h"
#include "renderer/VideoWriter.h"
#include "service/ChromeTrace.h"

namespace service {

namespace fs = std::filesystem;

const char* modeName(hlod::FrameMode mode) {
  return mode == hlod::FrameMode::Settled ? "settled" : "realtime";
}

hlod::Result<hlod::FrameMode> parseMode(const std::string& name) {
  if (name == "realtime") return hlod::FrameMode::Realtime;
  if (name == "settled") return hlod::FrameMode::Settled;
  return hlod::makeError("mode must be realtime or settled (not '" + name + "')");
}

namespace {

hlod::Status validate(const hlod::NodeSource* source, const SessionOptions& o) {
  if (!source) return hlod::makeError("no node source");
  if (o.width < 1 || o.height < 1 || o.width > renderer::Renderer::kMaxSize ||
      o.height > renderer::Renderer::kMaxSize)
    return hlod::makeError("frame size must be between 1x1 and 8192x8192");
  if (!(o.budgetMs > 0.0) || !std::isfinite(o.budgetMs))
    return hlod::makeError("the frame budget must be a positive number of ms");
  if (source->skeleton().roots.empty()) return hlod::makeError("the node store has no nodes");
  return hlod::Ok{};
}

}  // namespace

hlod::Result<std::unique_ptr<Session>> Session::create(
    std::shared_ptr<const hlod::NodeSource> source, const SessionOptions& options,
    renderer::GlContext& context) {
  if (auto v = validate(source.get(), options); !v) return v.error();
  std::unique_ptr<Session> s(new Session());
  s->options_ = options;
  s->source_ = std::move(source);
  if (auto st = s->init(context); !st) return st.error();
  return s;
}

hlod::Result<std::unique_ptr<Session>> Session::create(
    std::shared_ptr<const hlod::NodeSource> source, const SessionOptions& options,
    renderer::Backend backend) {
  if (auto v = validate(source.get(), options); !v) return v.error();
  auto context = renderer::createContext(backend);
  if (!context) return context.error();
  std::unique_ptr<Session> s(new Session());
  s->options_ = options;
  s->source_ = std::move(source);
  s->ownContext_ = std::move(*context);
  if (auto st = s->init(*s->ownContext_); !st) return st.error();
  return s;
}

hlod::Result<std::unique_ptr<Session>> Session::open(const fs::path& store,
                                                     const SessionOptions& options,
                                                     renderer::Backend backend) {
  std::error_code ec;
  if (!fs::is_directory(store, ec) || !fs::exists(store / "skeleton.bin", ec))
    return hlod::makeError(store.string() +
                           " is not a node store (a folder with skeleton.bin; make one with "
                           "`hlodr build`)");
  auto opened = hlod::NodeStore::open(store);
  if (!opened) return hlod::makeError(store.string() + ": " + opened.message());
  std::shared_ptr<const hlod::NodeSource> source(std::move(*opened));
  return create(std::move(source), options, backend);
}

hlod::Status Session::init(renderer::GlContext& context) {
  context_ = &context;
  if (!context_->makeCurrent()) return hlod::makeError("cannot make the GL context current");
  const hlod::Skeleton& skel = source_->skeleton();
  hlod::SelectorParams sp = options_.selectorParams;
  sp.lakhia.c_targetTime = options_.budgetMs;
  renderer::RenderOptions ro;
  ro.width = options_.width;
  ro.height = options_.height;
  ro.effects = options_.effects;
  // Sky, hemisphere light and shadow map stand on it (an earth-centred store's ellipsoid normal).
  ro.up = hlod::modelUpFrame(skel).up;
  std::unique_ptr<hlod::Selector> selector, ahead;
  if (options_.selector == "vdr") {
    if (auto v = initVdr(ro, sp, selector); !v) return v;
  } else {
    auto sel = hlod::makeSelector(options_.selector, skel, sp);
    if (!sel) return sel.error();
    auto next = hlod::makeSelector(options_.selector, skel, sp);
    if (!next) return next.error();
    selector = std::move(*sel);
    ahead = std::move(*next);
    auto r = renderer::GpuNodeRenderer::create(*context_, skel, ro);
    if (!r) return r.error();
    renderer_ = std::move(*r);
  }

  hlod::LoaderParams lp;
  lp.capBytes = options_.memoryCapBytes;
  lp.ioMbps = options_.ioMbps;
  lp.ioLatencyMs = options_.ioLatencyMs;
  lp.ioRequests = options_.ioRequests;
  lp.cache = options_.cache;
  // No textures declared: the loader never reads them, and its texture-less meshes are cached
  // apart from those of textured sessions of the same store.
  lp.textures = options_.effects.textures;
  lp.cacheStore =
      options_.effects.textures ? options_.cacheStore : options_.cacheStore | 0x80000000u;
  loader_ = std::make_unique<hlod::Loader>(*source_, lp);

  hlod::FrameDriverOptions fo;
  fo.uploadBudgetMs = options_.uploadBudgetMs;
  fo.uploadBudgetBytes = options_.uploadBudgetBytes;
  fo.prefetchWeight = options_.prefetchWeight;
  fo.settleTimeout = options_.settleTimeout;
  fo.width = options_.width;
  fo.height = options_.height;
  fo.recentFrames = options_.recentFrames;
  fo.occlusion = options_.occlusion;
  fo.gpuBudgetBytes = options_.gpuBudgetBytes;
  fo.renderWhileLoading = options_.renderWhileLoading;
  fo.predict = options_.predict;
  // The view-dependent clusters are not culled by queries yet: "vdr" draws without culling.
  if (vdrRenderer_) fo.occlusion = hlod::OcclusionMode::Off;
  gpu().setShowOcclusion(options_.showOcclusion);
  // A declared density culls what it hides; a derived one (1 / far) never reaches the model.
  if (options_.effects.fog && options_.effects.fog->density > 0.0)
    fo.fogCullDistance = hlod::fogCullDistance(options_.effects.fog->density);
  hlod::NodeRenderer& nodes =
      vdrRenderer_ ? static_cast<hlod::NodeRenderer&>(*vdrRenderer_) : *renderer_;
  driver_ = std::make_unique<hlod::FrameDriver>(std::move(selector), std::move(ahead), *loader_,
                                                nodes, fo);
  return driver_->start(options_.knownVTime, options_.knownFixedMs);
}

std::string Session::loadFailure() const {
  const hlod::LoaderCounters lc = loader_->counters();
  if (lc.loadErrors == 0) return "";
  return std::to_string(lc.loadErrors) +
         " node(s) of the store failed to load and were drawn coarser (last: " +
         loader_->lastError() + "); the store is damaged, rebuild it with `hlodr build`";
}

hlod::Status Session::initVdr(const renderer::RenderOptions& ro, const hlod::SelectorParams& sp,
                              std::unique_ptr<hlod::Selector>& selector) {
  const auto* store = dynamic_cast<const hlod::NodeStore*>(source_.get());
  if (!store)
    return hlod::makeError("the vdr selector draws a node store's view-dependent section");
  auto runtime = hlod::vdr::VdrRuntime::open(*store);
  if (!runtime) return runtime.error();
  vdr_ = std::move(*runtime);
  selector = std::make_unique<hlod::VdrSelector>(*vdr_, sp);
  auto r = renderer::VdrNodeRenderer::create(*context_, *vdr_, ro, options_.vdrMinActiveRatio,
                                             options_.vdrGpuBudgetBytes);
  if (!r) return r.error();
  vdrRenderer_ = std::move(*r);
  return hlod::Ok{};
}

Session::~Session() {
  if (loader_) loader_->stop();
  // GL objects are deleted through the context: it must be current while they die.
  if (context_) context_->makeCurrent();
  driver_.reset();
  loader_.reset();
  renderer_.reset();
  vdrRenderer_.reset();
  vdr_.reset();
}

hlod::Result<hlod::FrameRecord> Session::renderFrame(const hlod::CameraSample& sample,
                                                     hlod::FrameMode mode,
                                                     const hlod::CameraSample* lookahead) {
  if (!context_->makeCurrent()) return hlod::makeError("cannot make the GL context current");
  return driver_->renderFrame(sample, mode, lookahead);
}

hlod::Image Session::readback() {
  context_->makeCurrent();
  return gpu().readback();
}

hlod::metrics::Mask Session::coverage() {
  context_->makeCurrent();
  return gpu().coverage();
}

hlod::FrameSummary Session::recentSummary() const {
  const std::vector<hlod::FrameRecord> frames(recent().begin(), recent().end());
  return hlod::summarize(frames);
}

std::string Session::settingsJson() const {
  nlohmann::json j = {{"selector", options_.selector},
                      {"width", options_.width},
                      {"height", options_.height},
                      {"budgetMs", options_.budgetMs},
                      {"uploadBudgetMs", options_.uploadBudgetMs},
                      {"memoryCapBytes", options_.memoryCapBytes},
                      {"startVTime", driver_->selector().vTime()},
                      {"gl", renderer::describe(context_->info())}};
  return j.dump();
}

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(a) == std::tolower(b); });
}

}  // namespace

hlod::Result<FileRunResult> runPathToFiles(Session& session, const hlod::CameraPath& path,
                                           const hlod::PathRunOptions& run,
                                           const FileOutputs& outputs,
                                           const hlod::FrameCallback& onFrame,
                                           const std::atomic<bool>* cancel) {
  // Where the outputs go: a folder (PNGs + stats.json ...) or beside an .mp4 (STEM.stats.json).
  const auto& so = session.options();
  std::vector<std::unique_ptr<hlod::FrameSink>> sinks;
  fs::path statsDir;
  std::string prefix;
  std::error_code ec;
  if (!outputs.output.empty() && endsWith(outputs.output.string(), ".mp4")) {
    statsDir = outputs.output.parent_path();
    if (statsDir.empty()) statsDir = ".";
    prefix = outputs.output.stem().string() + ".";
    fs::create_directories(statsDir, ec);
    auto v = renderer::VideoWriter::open(outputs.output, so.width, so.height, run.fps);
    if (!v) return v.error();
    sinks.push_back(std::make_unique<renderer::VideoSink>(std::move(*v)));
  } else {
    statsDir = outputs.output.empty() ? outputs.statsDir : outputs.output;
    if (statsDir.empty()) return hlod::makeError("no output folder given");
    fs::create_directories(statsDir, ec);
    if (!fs::is_directory(statsDir))
      return hlod::makeError("cannot create the folder " + statsDir.string());
    if (!outputs.output.empty())
      sinks.push_back(std::make_unique<renderer::ImageSequenceSink>(outputs.output));
  }
  FileRunResult result;
  result.statsJson = statsDir / (prefix + "stats.json");
  result.statsCsv = statsDir / (prefix + "stats.csv");
  nlohmann::json extraJson = {{"session", nlohmann::json::parse(session.settingsJson())},
                              {"mode", modeName(run.mode)},
                              {"fps", run.fps}};
  if (run.segmentCount > 1) {
    // What `hlodr concat` checks before it joins the segments: which one, of how many frames.
    auto total = hlod::runFrameCount(path, run);
    if (!total) return total.error();
    if (run.segmentIndex >= run.segmentCount || run.segmentCount > *total)
      return hlod::makeError("cannot split " + std::to_string(*total) + " frames into " +
                             std::to_string(run.segmentCount) + " segments");
    const hlod::FrameRange r = hlod::segmentRange(*total, run.segmentIndex, run.segmentCount);
    extraJson["segment"] = {
        {"index", run.segmentIndex}, {"count", run.segmentCount},
        {"firstFrame", r.first},     {"endFrame", r.end},
        {"runFrames", *total},       {"warmupFrames", std::min(run.warmupFrames, r.first)}};
  }
  const std::string extra = extraJson.dump();
  auto stats =
      std::make_unique<hlod::StatsSink>(result.statsJson.string(), result.statsCsv.string(),
                                        outputs.plots ? (statsDir / prefix).string() : "", extra);
  hlod::StatsSink* statsSink = stats.get();
  sinks.push_back(std::move(stats));
  if (!outputs.trace.empty())
    sinks.push_back(std::make_unique<ChromeTraceSink>(outputs.trace.string(), "hlodr render",
                                                      nlohmann::json::parse(extra)));

  std::vector<hlod::FrameSink*> list;
  for (auto& s : sinks) list.push_back(s.get());
  auto ran = hlod::runPath(session.driver(), path, run, list, cancel, onFrame);
  if (!ran) return ran.error();
  result.run = *ran;
  result.summary = hlod::summarize(statsSink->frames());
  for (const auto& p : statsSink->plotPaths()) result.plots.push_back(p);
  return result;
}

}  // namespace service
