// A viewing session along a camera path: the render thread's side of Lakhia III-C/D (front
// selection with v_time feedback, the loading thread fed with load priorities) and Manocha 5.5
// (render while loading: nodes not yet on the GPU are drawn at a coarser level, never waited for).
#include "service/PathSession.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "hlod/Loader.h"
#include "hlod/NodeStore.h"
#include "hlod/Plots.h"
#include "renderer/FrameView.h"
#include "renderer/GpuMesh.h"
#include "service/SceneLoading.h"

namespace service {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Bytes an upload moves to the GL: vertex attributes, indices and the texture.
std::uint64_t uploadBytesOf(const hlod::LocalMesh& m) {
  std::uint64_t b = m.positions.size() * 12 + m.normals.size() * 12 + m.texCoords.size() * 8 +
                    m.indices.size() * 4;
  if (m.texture) b += static_cast<std::uint64_t>(m.texture->pixels.size());
  return b;
}

}  // namespace

struct PathSession::State {
  std::unique_ptr<renderer::Renderer> renderer;
  std::unordered_map<std::uint32_t, renderer::GpuMesh> gpu;  // GPU copies by node id
  hlod::ResidencySet gpuResident;                            // what the selector may draw
  // Loaded payloads waiting for an upload, in load order (parents before children).
  std::deque<std::pair<std::uint32_t, std::shared_ptr<const hlod::LocalMesh>>> pending;
  std::unique_ptr<hlod::Selector> prefetchSelector;  // own hysteresis state for cameras ahead
  hlod::Aabb bounds;                                 // of the whole model (clip planes)
  std::unique_ptr<hlod::Loader> loader;              // last: its thread stops first
};

hlod::Result<std::unique_ptr<PathSession>> PathSession::open(const fs::path& store,
                                                             const PathSessionOptions& options) {
  std::error_code ec;
  if (!fs::is_directory(store, ec) || !fs::exists(store / "skeleton.bin", ec))
    return hlod::makeError(store.string() +
                           " is not a node store (a folder with skeleton.bin; make one with "
                           "`hlodr build`)");
  auto opened = hlod::NodeStore::open(store);
  if (!opened) return hlod::makeError(store.string() + ": " + opened.message());
  std::shared_ptr<const hlod::NodeSource> source(std::move(*opened));
  return create(std::move(source), options);
}

hlod::Result<std::unique_ptr<PathSession>> PathSession::create(
    std::shared_ptr<const hlod::NodeSource> source, const PathSessionOptions& options) {
  if (!source) return hlod::makeError("no node source");
  if (options.width < 1 || options.height < 1 || options.width > renderer::Renderer::kMaxSize ||
      options.height > renderer::Renderer::kMaxSize)
    return hlod::makeError("frame size must be between 1x1 and 8192x8192");
  if (!(options.budgetMs > 0.0) || !std::isfinite(options.budgetMs))
    return hlod::makeError("the frame budget must be a positive number of ms");
  if (source->skeleton().roots.empty()) return hlod::makeError("the node store has no nodes");
  std::unique_ptr<PathSession> s(new PathSession());
  s->options_ = options;
  s->source_ = std::move(source);
  auto status = s->init();
  if (!status) return status.error();
  return s;
}

hlod::Status PathSession::init() {
  const hlod::Skeleton& skel = source_->skeleton();
  hlod::SelectorParams sp = options_.selectorParams;
  sp.lakhia.c_targetTime = options_.budgetMs;
  auto sel = hlod::makeSelector(options_.selector, skel, sp);
  if (!sel) return sel.error();
  selector_ = std::move(*sel);
  auto ahead = hlod::makeSelector(options_.selector, skel, sp);
  if (!ahead) return ahead.error();

  auto context = renderer::createContext(options_.backend);
  if (!context) return context.error();
  context_ = std::move(*context);

  state_ = std::make_unique<State>();
  State& st = *state_;
  st.prefetchSelector = std::move(*ahead);
  for (std::uint32_t r : skel.roots)
    if (r < skel.nodes.size()) st.bounds.extend(skel.nodes[r].bounds);
  st.gpuResident = hlod::ResidencySet(skel.nodes.size());

  renderer::RenderOptions ro;
  ro.width = options_.width;
  ro.height = options_.height;
  ro.effects = options_.effects;
  auto r = renderer::Renderer::create(*context_, ro);
  if (!r) return r.error();
  st.renderer = std::move(*r);

  hlod::LoaderParams lp;
  lp.capBytes = options_.memoryCapBytes;
  lp.ioMbps = options_.ioMbps;
  lp.ioLatencyMs = options_.ioLatencyMs;
  lp.ioRequests = options_.ioRequests;
  st.loader = std::make_unique<hlod::Loader>(*source_, lp);
  auto roots = st.loader->loadRoots();
  if (!roots) return roots.error();

  // hlod_0 is what everything falls back to: on the GPU before the first frame, unbudgeted.
  for (auto& e : st.loader->drainEvents()) {
    if (e.kind != hlod::LoaderEvent::Kind::Loaded || !e.mesh) continue;
    auto gpu = renderer::GpuMesh::upload(st.renderer->gl(), *e.mesh);
    if (!gpu) return hlod::makeError("node " + std::to_string(e.node) + ": " + gpu.message());
    st.gpu.insert_or_assign(e.node, std::move(*gpu));
    st.gpuResident.set(e.node, true);
  }
  // Warm-up draw of hlod_0: first-use costs (shader JIT, texture residency) are not frame 0.
  if (!st.bounds.empty()) {
    std::vector<const renderer::GpuMesh*> all;
    for (const auto& [node, mesh] : st.gpu) all.push_back(&mesh);
    const glm::dvec3 c = st.bounds.centre();
    const double d = std::max(glm::length(st.bounds.max - st.bounds.min), 1e-3);
    st.renderer->drawFrame(
        renderer::makeFrameView(c + glm::dvec3(0.0, -d, d), c, {0.0, 0.0, 1.0}, 60.0,
                                static_cast<double>(options_.width) / options_.height, d * 1e-3,
                                d * 4.0),
        all);
  }
  st.loader->start();
  return hlod::Ok{};
}

PathSession::~PathSession() {
  if (state_ && state_->loader) state_->loader->stop();
  // GL objects are deleted through the context: it must be current while they die.
  if (context_) context_->makeCurrent();
  state_.reset();
}

hlod::LoaderCounters PathSession::loaderCounters() const {
  return state_->loader->counters();
}
std::size_t PathSession::gpuNodeCount() const {
  return state_->gpu.size();
}

hlod::Image PathSession::readback() {
  context_->makeCurrent();
  return state_->renderer->readback();
}

hlod::Result<hlod::FrameRecord> PathSession::renderFrame(const hlod::CameraSample& sample,
                                                         const hlod::CameraSample* lookahead) {
  const auto frameStart = Clock::now();
  if (!context_->makeCurrent()) return hlod::makeError("cannot make the GL context current");
  State& st = *state_;
  const bool settled = options_.mode == PathMode::Settled;
  FrameExtras ex;
  double waitMs = 0.0;

  // Loader events since the last frame: an unloaded node loses its GPU copy now (the resident
  // set stays closed upwards: the loader unloads children first); a loaded one queues.
  auto drain = [&] {
    for (auto& e : st.loader->drainEvents()) {
      if (e.kind == hlod::LoaderEvent::Kind::Loaded) {
        if (e.mesh) st.pending.emplace_back(e.node, std::move(e.mesh));
      } else {
        st.gpu.erase(e.node);
        st.gpuResident.set(e.node, false);
        std::erase_if(st.pending, [&](const auto& p) { return p.first == e.node; });
      }
    }
  };
  // Uploads queued nodes in order until the time or byte budget is spent (at least one, so
  // uploads always progress). A failed upload is an Error.
  auto upload = [&](double budgetMs, std::uint64_t budgetBytes) -> hlod::Status {
    const auto start = Clock::now();
    std::uint32_t done = 0;
    std::uint64_t bytes = 0;
    while (!st.pending.empty()) {
      if (done > 0 && (msSince(start) >= budgetMs || (budgetBytes > 0 && bytes >= budgetBytes)))
        break;
      auto [node, mesh] = std::move(st.pending.front());
      st.pending.pop_front();
      auto gpu = renderer::GpuMesh::upload(st.renderer->gl(), *mesh);
      if (!gpu) return hlod::makeError("node " + std::to_string(node) + ": " + gpu.message());
      st.gpu.insert_or_assign(node, std::move(*gpu));
      st.gpuResident.set(node, true);
      ++done;
      bytes += uploadBytesOf(*mesh);
    }
    ex.uploads += done;
    ex.uploadBytes += bytes;
    return hlod::Ok{};
  };

  drain();
  const auto uploadStart = Clock::now();
  if (!settled) {
    if (auto u = upload(options_.uploadBudgetMs, options_.uploadBudgetBytes); !u) return u.error();
  }
  ex.uploadMs = msSince(uploadStart);

  hlod::View view{sample.camera, sample.velocity, options_.width, options_.height};
  // This frame's uploads are done: the drawing gets the rest of the budget.
  view.spentMs = settled ? 0.0 : ex.uploadMs;
  view.camera.aspect = static_cast<double>(options_.width) / options_.height;
  const auto selectStart = Clock::now();
  // Settled: select as if everything were resident; that front is then loaded before drawing.
  const hlod::AllResident allResident;
  hlod::Selection sel =
      selector_->select(view, settled ? static_cast<const hlod::Residency&>(allResident)
                                      : static_cast<const hlod::Residency&>(st.gpuResident));
  double selectorMs = msSince(selectStart);
  st.loader->setWanted(sel.loadPriorities);

  // Known-path prefetch: the selection for a camera further along the path, at lower priority.
  if (lookahead) {
    hlod::View ahead{lookahead->camera, lookahead->velocity, options_.width, options_.height};
    ahead.camera.aspect = view.camera.aspect;
    st.prefetchSelector->setVTime(selector_->vTime());
    hlod::Selection future = st.prefetchSelector->select(ahead, allResident);
    for (auto& r : future.loadPriorities) r.priority *= options_.prefetchWeight;
    st.loader->prefetch(future.loadPriorities);
  }

  std::uint32_t stalls = 0;
  if (settled) {
    auto onGpu = [&] {
      return std::all_of(sel.front.begin(), sel.front.end(),
                         [&](std::uint32_t n) { return st.gpuResident.isResident(n); });
    };
    if (!onGpu()) {
      // Settled uploads are unbudgeted and, like the wait, not part of the frame time.
      const auto waitStart = Clock::now();
      const bool loaded = std::all_of(sel.front.begin(), sel.front.end(),
                                      [&](std::uint32_t n) { return st.loader->isResident(n); });
      if (!loaded) {
        // The renderer has to wait for the loader: a stall.
        stalls = 1;
        st.loader->waitUntilResident(sel.front, options_.settleTimeout);
      }
      drain();
      const auto settleUpload = Clock::now();
      if (auto u = upload(1e300, 0); !u) return u.error();
      ex.uploadMs += msSince(settleUpload);
      if (!onGpu()) {
        // Memory cap or timeout: the front does not fit. Draw what is there, coarser.
        sel = selector_->select(view, st.gpuResident);
        st.loader->setWanted(sel.loadPriorities);
      }
      waitMs = msSince(waitStart);
    }
  }

  renderer::FrameView fv;
  {
    CameraPose pose{view.camera.position, view.camera.target, view.camera.up, view.camera.fovY};
    double zNear = view.camera.nearPlane, zFar = view.camera.farPlane;
    if (!st.bounds.empty()) clipPlanes(pose, st.bounds, zNear, zFar);
    fv = renderer::makeFrameView(pose.position, pose.target, pose.up, pose.fovY, view.camera.aspect,
                                 zNear, zFar);
  }
  // Front to back: the depth test then rejects hidden fragments before they are shaded, which on
  // a software rasteriser is most of a street-level frame (the near blocks hide the rest).
  std::vector<std::pair<double, const renderer::GpuMesh*>> ordered;
  ordered.reserve(sel.front.size());
  for (std::uint32_t n : sel.front) {
    auto it = st.gpu.find(n);
    if (it == st.gpu.end()) continue;
    const hlod::Aabb& b = source_->skeleton().nodes[n].bounds;
    const glm::dvec3 nearest = glm::clamp(view.camera.position, b.min, b.max);
    const glm::dvec3 d = nearest - view.camera.position;
    ordered.emplace_back(glm::dot(d, d), &it->second);
  }
  std::stable_sort(ordered.begin(), ordered.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<const renderer::GpuMesh*> drawList;
  drawList.reserve(ordered.size());
  for (const auto& [d2, mesh] : ordered) drawList.push_back(mesh);
  const renderer::FrameTiming timing = st.renderer->drawFrame(fv, drawList);

  // Frame time: this frame's uploads plus the GL work through glFinish (settled-mode uploads
  // belong to the stall, not to the frame). v_time learns from the drawing alone.
  const double frameMs = (settled ? 0.0 : ex.uploadMs) + timing.cpuMs;
  selector_->feedback(timing.cpuMs);

  ex.queryGpuMs = timing.gpuMs;
  ex.drawMs = timing.cpuMs;
  ex.pendingUploads = static_cast<std::uint32_t>(st.pending.size());

  hlod::FrameRecord rec;
  rec.index = frames_.size();
  rec.time = sample.time;
  hlod::fillFromSelection(rec, sel);
  hlod::fillFromLoader(rec, st.loader->counters());
  rec.triangles = timing.triangles;  // what was drawn (equal to the front's numTri sum)
  rec.gpuMs = frameMs;
  rec.cpuMs = msSince(frameStart) - waitMs;
  rec.selectorMs = selectorMs;
  rec.stalls = stalls;
  frames_.push_back(rec);
  extras_.push_back(ex);
  return rec;
}

hlod::Status PathSession::writeStats(const fs::path& jsonPath, const fs::path& csvPath) const {
  // The FrameStats JSON, with this session's extra per-frame measurements added.
  auto json = nlohmann::json::parse(hlod::statsJson(frames_, summary()), nullptr, false);
  if (json.is_discarded()) return hlod::makeError("internal: stats JSON did not parse");
  auto& frames = json["frames"];
  for (std::size_t i = 0; i < extras_.size() && i < frames.size(); ++i) {
    const FrameExtras& e = extras_[i];
    frames[i]["queryGpuMs"] = e.queryGpuMs;
    frames[i]["drawMs"] = e.drawMs;
    frames[i]["uploadMs"] = e.uploadMs;
    frames[i]["uploads"] = e.uploads;
    frames[i]["uploadBytes"] = e.uploadBytes;
    frames[i]["pendingUploads"] = e.pendingUploads;
  }
  json["session"] = {{"selector", options_.selector},
                     {"mode", options_.mode == PathMode::Settled ? "settled" : "realtime"},
                     {"width", options_.width},
                     {"height", options_.height},
                     {"budgetMs", options_.budgetMs},
                     {"uploadBudgetMs", options_.uploadBudgetMs},
                     {"gl", renderer::describe(context_->info())}};
  std::ofstream out(jsonPath, std::ios::binary);
  out << json.dump(1) << '\n';
  out.close();
  if (!out) return hlod::makeError("cannot write " + jsonPath.string());
  return hlod::writeStatsCsv(csvPath.string(), frames_);
}

hlod::Status PathSession::writePlots(const fs::path& dir, const std::string& prefix) const {
  const std::pair<const char*, std::string> plots[] = {
      {"levels.svg", hlod::levelsSvg(frames_)},
      {"toggles.svg", hlod::togglesSvg(frames_)},
      {"frametime.svg", hlod::frameTimeSvg(frames_)},
  };
  for (const auto& [name, svg] : plots) {
    auto s = hlod::writeSvg((dir / (prefix + name)).string(), svg);
    if (!s) return s;
  }
  return hlod::Ok{};
}

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(a) == std::tolower(b); });
}

bool onPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string p(path);
  std::size_t start = 0;
  while (start <= p.size()) {
    std::size_t end = p.find(':', start);
    if (end == std::string::npos) end = p.size();
    const std::string dir = p.substr(start, end - start);
    if (!dir.empty() && ::access((dir + "/" + program).c_str(), X_OK) == 0) return true;
    start = end + 1;
  }
  return false;
}

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Raw RGBA frames piped to ffmpeg (libx264, yuv420p). SIGPIPE is ignored while it is open so an
// ffmpeg that dies makes fwrite fail instead of killing the process.
class VideoPipe {
 public:
  static hlod::Result<std::unique_ptr<VideoPipe>> open(const fs::path& path, int w, int h,
                                                       double fps) {
    if (!onPath("ffmpeg"))
      return hlod::makeError("writing " + path.string() +
                             " needs ffmpeg on the PATH (install ffmpeg, or give a folder for a "
                             "PNG sequence)");
    if (w % 2 || h % 2)
      return hlod::makeError("an .mp4 (yuv420p) needs an even frame width and height");
    char rate[32];
    std::snprintf(rate, sizeof rate, "%g", fps);
    // Niced and single-threaded: the encoder is background work and must not take the cores
    // the frames are timed on (on 2 cores, a free-running libx264 put 11% of them over 1.25x).
    const std::string cmd = "nice -n 19 ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgba -s " +
                            std::to_string(w) + "x" + std::to_string(h) + " -r " + rate +
                            " -i - -c:v libx264 -preset veryfast -threads 1 -pix_fmt yuv420p " +
                            shellQuote(path.string());
    std::unique_ptr<VideoPipe> v(new VideoPipe());
    v->oldHandler_ = std::signal(SIGPIPE, SIG_IGN);
    v->pipe_ = ::popen(cmd.c_str(), "w");
    if (!v->pipe_) return hlod::makeError("cannot start ffmpeg: " + std::string(strerror(errno)));
    v->path_ = path;
    return v;
  }
  ~VideoPipe() {
    if (pipe_) ::pclose(pipe_);
    std::signal(SIGPIPE, oldHandler_);
  }
  hlod::Status write(const hlod::Image& image) {
    if (std::fwrite(image.pixels.data(), 1, image.pixels.size(), pipe_) != image.pixels.size())
      return hlod::makeError("ffmpeg stopped taking frames for " + path_.string());
    return hlod::Ok{};
  }
  hlod::Status close() {
    const int st = ::pclose(pipe_);
    pipe_ = nullptr;
    if (st != 0) return hlod::makeError("ffmpeg failed writing " + path_.string());
    return hlod::Ok{};
  }

 private:
  VideoPipe() = default;
  std::FILE* pipe_ = nullptr;
  fs::path path_;
  void (*oldHandler_)(int) = SIG_DFL;
};

}  // namespace

hlod::Result<PathRunResult> runPath(PathSession& session, const hlod::CameraPath& path,
                                    const PathRunOptions& options) {
  if (!(options.fps > 0.0) || options.fps > 1000.0)
    return hlod::makeError("fps must be in (0, 1000]");
  const auto& so = session.options();
  const double aspect = static_cast<double>(so.width) / so.height;
  const std::vector<hlod::CameraSample> samples = path.sampleAt(options.fps, aspect);
  std::size_t count = samples.size();
  if (options.maxFrames >= 0) count = std::min<std::size_t>(count, options.maxFrames);

  // Where the outputs go: a folder (PNGs + stats.json ...) or beside an .mp4 (STEM.stats.json).
  PathRunResult result;
  std::unique_ptr<VideoPipe> video;
  fs::path imageDir, statsDir;
  std::string prefix;
  std::error_code ec;
  if (!options.output.empty() && endsWith(options.output.string(), ".mp4")) {
    statsDir = options.output.parent_path();
    if (statsDir.empty()) statsDir = ".";
    prefix = options.output.stem().string() + ".";
    fs::create_directories(statsDir, ec);
    auto v = VideoPipe::open(options.output, so.width, so.height, options.fps);
    if (!v) return v.error();
    video = std::move(*v);
  } else {
    imageDir = options.output;
    statsDir = options.output.empty() ? options.statsDir : options.output;
    if (statsDir.empty()) return hlod::makeError("no output folder given");
    fs::create_directories(statsDir, ec);
    if (!fs::is_directory(statsDir))
      return hlod::makeError("cannot create the folder " + statsDir.string());
  }

  const std::size_t ahead =
      options.prefetchSeconds > 0.0
          ? static_cast<std::size_t>(std::lround(options.prefetchSeconds * options.fps))
          : 0;
  const bool progress = options.progress && ::isatty(STDERR_FILENO);
  for (std::size_t i = 0; i < count; ++i) {
    const hlod::CameraSample* look = nullptr;
    if (ahead > 0) look = &samples[std::min(i + ahead, samples.size() - 1)];
    auto rec = session.renderFrame(samples[i], look);
    if (!rec) return hlod::makeError("frame " + std::to_string(i) + ": " + rec.message());
    if (video || !imageDir.empty()) {
      const hlod::Image image = session.readback();
      if (video) {
        if (auto w = video->write(image); !w) return w.error();
      } else {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%05zu.png", i);
        if (auto w = renderer::writeImage((imageDir / name).string(), image); !w) return w.error();
      }
    }
    if (progress)
      std::fprintf(stderr, "\rframe %zu/%zu  %6.1f ms (target %.0f)  %9llu triangles  ", i + 1,
                   count, rec->gpuMs, rec->targetMs,
                   static_cast<unsigned long long>(rec->triangles));
  }
  if (progress) std::fprintf(stderr, "\n");
  if (video) {
    if (auto c = video->close(); !c) return c.error();
  }
  result.framesRendered = count;
  result.statsJson = statsDir / (prefix + "stats.json");
  result.statsCsv = statsDir / (prefix + "stats.csv");
  if (auto s = session.writeStats(result.statsJson, result.statsCsv); !s) return s.error();
  if (options.plots) {
    if (auto s = session.writePlots(statsDir, prefix); !s) return s.error();
    for (const char* n : {"levels.svg", "toggles.svg", "frametime.svg"})
      result.plots.push_back(statsDir / (prefix + n));
  }
  result.summary = session.summary();
  return result;
}

}  // namespace service
