// The accuracy study's renders. See service/Study.h.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <vector>

#include "hlod/metrics/ImageMetrics.h"
#include "hlod/runtime/LinkClock.h"
#include "renderer/ImageEncoder.h"
#include "service/BatchedReference.h"
#include "service/ChromeTrace.h"
#include "service/Session.h"
#include "service/Study.h"

namespace service {

namespace fs = std::filesystem;
using namespace hlod::study;

namespace {

// Frames a budgeted selector may take to come to rest at a studied camera (settled runs).
constexpr int kSettleFrames = 16;
// Frames drawn at a studied camera once it is at rest, in settled runs, by every selector
// alike: the frame time is their median. One draw's time on a shared machine moves by 10-20%,
// and the first frame after the metrics of the last camera was not timed like a frame after
// frames (Lakhia's, after its settling frames).
constexpr int kTimedFrames = 3;
// The calibration pass before each budgeted run: frames at most at a studied camera, and
// the change of v_time in a frame below which it counts as at rest there.
constexpr int kCalibrationFrames = 48;
constexpr double kSteadyVTime = 0.02;

// The studied frames: `count` path frames spread evenly from the first to the last.
std::vector<std::uint64_t> studiedFrames(std::uint64_t total, std::size_t count) {
  std::vector<std::uint64_t> out;
  if (total == 0 || count == 0) return out;
  count = static_cast<std::size_t>(std::min<std::uint64_t>(count, total));
  for (std::size_t i = 0; i < count; ++i)
    out.push_back(count == 1 ? 0
                             : std::uint64_t(std::llround(double(i) * double(total - 1) /
                                                          double(count - 1))));
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

struct Measured {
  FrameResult result;
  hlod::Image image;
  std::vector<float> flipMap;
  hlod::metrics::Mask coverage;
};

}  // namespace

hlod::Result<StudyReport> runStudy(std::shared_ptr<const hlod::NodeSource> source,
                                   const hlod::CameraPath& path, const StudyOptions& o,
                                   const fs::path& outDir, const nlohmann::json& settings,
                                   const StudyProgress& progress, const std::atomic<bool>* cancel,
                                   renderer::GlContext* given) {
  if (o.budgets.empty() &&
      std::find(o.selectors.begin(), o.selectors.end(), "sse") == o.selectors.end())
    return hlod::makeError("no budget to study");
  if (!o.settled && !o.realtime) return hlod::makeError("no mode to study");
  auto total = path.frameCount(o.fps);
  if (!total) return total.error();
  const std::vector<std::uint64_t> frames = studiedFrames(*total, o.frames);
  std::error_code ec;
  fs::create_directories(outDir, ec);
  if (!fs::is_directory(outDir, ec))
    return hlod::makeError("cannot create the folder " + outDir.string());

  std::unique_ptr<renderer::GlContext> own;
  if (!given) {
    auto c = renderer::createContext(renderer::Backend::Auto);
    if (!c) return c.error();
    own = std::move(*c);
  }
  renderer::GlContext& gl = given ? *given : *own;
  const double aspect = double(o.width) / o.height;

  // The configurations, in the order they run.
  std::vector<StudyConfig> configs;
  for (bool realtime : {false, true}) {
    if (realtime ? !o.realtime : !o.settled) continue;
    for (const auto& sel : o.selectors) {
      if (sel == "sse") {
        for (double px : o.ssePx)
          configs.push_back(
              {sel, 33.0, px, realtime ? hlod::FrameMode::Realtime : hlod::FrameMode::Settled});
      } else {
        for (double b : o.budgets)
          configs.push_back(
              {sel, b, 0.0, realtime ? hlod::FrameMode::Realtime : hlod::FrameMode::Settled});
      }
    }
  }
  // Work, for the progress: reference frames, studied frames, and every realtime frame.
  double work = double(frames.size()), done = 0.0;
  for (const auto& c : configs)
    work += c.mode == hlod::FrameMode::Settled ? double(frames.size()) : double(frames.back() + 1);
  auto step = [&](const std::string& what) {
    done += 1.0;
    if (progress) progress(what, done / work);
  };
  auto cancelled = [&] { return cancel && cancel->load(); };

  SessionOptions base;
  base.width = o.width;
  base.height = o.height;
  base.memoryCapBytes = o.memoryCapBytes;
  base.recentFrames = 0;
  base.effects = o.effects;

  // The reference: full detail, once per studied frame, in batches within its memory cap.
  StudyReport report;
  report.settings = settings;
  std::vector<hlod::Image> refImages;
  std::vector<hlod::metrics::Mask> refMasks;
  {
    renderer::RenderOptions ro;
    ro.width = o.width;
    ro.height = o.height;
    ro.effects = o.effects;
    ro.up = hlod::upVector(source->skeleton().up);
    auto r = BatchedReference::create(source, ro, o.referenceCapBytes, gl);
    if (!r) return hlod::makeError("reference: " + r.message());
    for (std::uint64_t f : frames) {
      if (cancelled()) return hlod::makeError("cancelled");
      const hlod::CameraSample sample = path.sampleFrame(f, o.fps, aspect);
      auto drawn = (*r)->render(sample);
      if (!drawn)
        return hlod::makeError("reference frame " + std::to_string(f) + ": " + drawn.message());
      report.reference.push_back({f, sample.time, drawn->drawMs, drawn->triangles});
      refImages.push_back((*r)->readback());
      refMasks.push_back((*r)->coverage());
      step("reference frame " + std::to_string(f) + " (" + std::to_string(drawn->batches) +
           (drawn->batches == 1 ? " batch)" : " batches)"));
    }
  }

  // Strips: a few studied frames, shown at every Lakhia budget (settled).
  std::vector<std::size_t> stripAt;
  for (std::size_t k = 0; k < o.stripFrames && !frames.empty(); ++k)
    stripAt.push_back(
        std::min(frames.size() - 1,
                 (2 * k + 1) * frames.size() / (2 * std::max<std::size_t>(1, o.stripFrames))));
  stripAt.erase(std::unique(stripAt.begin(), stripAt.end()), stripAt.end());
  std::map<std::pair<std::size_t, double>, Measured> stripCells;  // (studied index, budget)

  // A budgeted run would start from the timing the run before left, as the server's sessions
  // do, and the first from FrameDriver::start's probe, which can be several times off either
  // way; a settled run's few frames per camera do not carry v_time to rest, so its first cameras
  // got fronts far under or over their budget, and two runs compared differed by where each
  // started. So each budgeted run starts from a calibration pass of its own selector and budget:
  // settled at every studied camera, unmeasured, from the timing the last run left.
  const auto sessionFor = [&](const StudyConfig& c) {
    SessionOptions so = base;
    so.selectorParams = o.selectorParams;
    so.selector = c.selector;
    so.budgetMs = c.budgetMs;
    so.selectorParams.ssePixels = c.ssePx > 0.0 ? c.ssePx : so.selectorParams.ssePixels;
    so.occlusion = o.occlusion;
    return so;
  };
  hlod::FrontTiming known;
  const auto calibrate = [&](const StudyConfig& c) -> hlod::Status {
    SessionOptions so = sessionFor(c);
    so.knownVTime = known.vTime;
    so.knownFixedMs = known.fixedMs;
    auto s = Session::create(source, so, gl);
    if (!s) return hlod::makeError(c.label() + ", calibration: " + s.message());
    if (!(*s)->selector().budgeted()) return hlod::Ok{};
    // At each studied camera until the front toggles nothing and v_time moved less than
    // kSteadyVTime in the last frame: a front held back by a v_time too high toggles nothing
    // while v_time comes down a few percent a frame.
    for (std::uint64_t f : frames) {
      if (cancelled()) return hlod::makeError("cancelled");
      double vTime = (*s)->driver().timing().vTime;
      for (int k = 0; k < kCalibrationFrames; ++k) {
        auto still =
            (*s)->renderFrame(path.sampleFrame(f, o.fps, aspect), hlod::FrameMode::Settled);
        if (!still)
          return hlod::makeError(c.label() + ", calibration, frame " + std::to_string(f) + ": " +
                                 still.message());
        const double next = (*s)->driver().timing().vTime;
        const bool steady = std::abs(next - vTime) <= kSteadyVTime * vTime;
        vTime = next;
        if (steady && still->upToggles + still->downToggles == 0) break;
      }
    }
    known = (*s)->driver().timing();
    return hlod::Ok{};
  };
  // --trace: every frame each run drew (settling and warm-up frames too), a process per run.
  std::vector<std::vector<hlod::FrameRecord>> traced;
  for (const StudyConfig& c : configs) {
    if (!o.trace.empty()) traced.emplace_back();
    if (c.selector != "sse")
      if (auto calibrated = calibrate(c); !calibrated) return calibrated.error();
    SessionOptions so = sessionFor(c);
    so.knownVTime = known.vTime;
    so.knownFixedMs = known.fixedMs;
    auto s = Session::create(source, so, gl);
    if (!s) return hlod::makeError(c.label() + ": " + s.message());
    Run run;
    run.config = c;
    std::uint64_t lastBytes = 0;
    std::size_t next = 0;  // the next studied frame
    const std::uint64_t last = frames.back();
    for (std::uint64_t f = c.mode == hlod::FrameMode::Settled ? frames.front() : 0; f <= last;
         ++f) {
      const bool studied = next < frames.size() && frames[next] == f;
      if (c.mode == hlod::FrameMode::Settled && !studied) continue;
      if (cancelled()) return hlod::makeError("cancelled");
      // A frame of the run; an error names the run and the path frame.
      auto render = [&](std::uint64_t frame) -> hlod::Result<hlod::FrameRecord> {
        auto rec = (*s)->renderFrame(path.sampleFrame(frame, o.fps, aspect), c.mode);
        if (!rec)
          return hlod::makeError(c.label() + ", frame " + std::to_string(frame) + ": " +
                                 rec.message());
        if (!traced.empty()) traced.back().push_back(*rec);
        return rec;
      };
      if (c.mode == hlod::FrameMode::Settled && o.occlusion != hlod::OcclusionMode::Off)
        for (std::uint64_t w = f - std::min<std::uint64_t>(f, 2); w < f; ++w)
          if (auto warm = render(w); !warm) return warm.error();
      // A budgeted selector's front follows its hysteresis, a step per frame: settled, it is
      // the front it comes to rest on with the camera held still at the studied frame (until a
      // frame toggles nothing, at most kSettleFrames), as SSE's is at once.
      if (c.mode == hlod::FrameMode::Settled && (*s)->selector().budgeted())
        for (int k = 0; k < kSettleFrames; ++k) {
          auto still = render(f);
          if (!still) return still.error();
          if (still->upToggles + still->downToggles == 0) break;
        }
      auto rec = render(f);
      if (!rec) return rec.error();
      std::vector<double> frameMs = {rec->gpuMs};
      for (int k = 1; c.mode == hlod::FrameMode::Settled && k < kTimedFrames; ++k) {
        rec = render(f);
        if (!rec) return rec.error();
        frameMs.push_back(rec->gpuMs);
      }
      // The last frame's front, image and counts; the frames' median time.
      std::nth_element(frameMs.begin(), frameMs.begin() + frameMs.size() / 2, frameMs.end());
      if (studied) {
        Measured m;
        FrameResult& r = m.result;
        r.frame = f;
        r.time = rec->time;
        r.frameMs = frameMs[frameMs.size() / 2];
        r.queryGpuMs = rec->queryGpuMs;
        r.triangles = rec->triangles;
        r.toggles = rec->upToggles + rec->downToggles;
        r.bytesLoaded = rec->bytesRead - lastBytes;
        lastBytes = rec->bytesRead;
        const auto readbackStart = std::chrono::steady_clock::now();
        m.image = (*s)->readback();
        if (!traced.empty() && !traced.back().empty()) {
          // The studied frame's readback, on the clock its timeline is on (the steady one).
          hlod::FrameTimeline& t = traced.back().back().timeline;
          t.readbackStartUs = hlod::microsecondsOf(readbackStart);
          t.readbackUs = hlod::microsecondsOf(std::chrono::steady_clock::now()) - t.readbackStartUs;
        }
        const hlod::Image& ref = refImages[next];
        auto p = hlod::metrics::psnr(ref, m.image);
        auto ss = hlod::metrics::ssim(ref, m.image);
        auto fm = hlod::metrics::flipMap(ref, m.image);
        hlod::metrics::Mask mask = (*s)->coverage();
        auto cov = hlod::metrics::coverageDifference(refMasks[next], mask);
        if (!p || !ss || !fm || !cov)
          return hlod::makeError("metrics failed on frame " + std::to_string(f));
        r.psnr = std::min(*p, kMaxPsnr);
        r.ssim = *ss;
        double sum = 0.0;
        for (float v : *fm) sum += v;
        r.flip = fm->empty() ? 0.0 : sum / double(fm->size());
        r.coverage = *cov;
        const hlod::CameraSample sample = path.sampleFrame(f, o.fps, aspect);
        hlod::View view{sample.camera, sample.velocity, o.width, o.height};
        view.camera.aspect = aspect;
        const auto e = frontScreenError((*s)->skeleton(), view, (*s)->driver().lastFront());
        r.sseMaxPx = e.maxPx;
        r.sseMeanPx = e.meanPx;
        run.frames.push_back(r);
        if (c.selector == "lakhia" && c.mode == hlod::FrameMode::Settled &&
            std::find(stripAt.begin(), stripAt.end(), next) != stripAt.end()) {
          m.flipMap = std::move(*fm);
          m.coverage = std::move(mask);
          stripCells[{next, c.budgetMs}] = std::move(m);
        }
        ++next;
      }
      step(c.label() + ", frame " + std::to_string(f));
    }
    if (const std::string failure = (*s)->loadFailure(); !failure.empty())
      return hlod::makeError(c.label() + ": " + failure);
    run.summary = summarize(run.frames);
    if ((*s)->selector().budgeted()) known = (*s)->driver().timing();
    report.runs.push_back(std::move(run));
  }
  if (!o.trace.empty()) {
    std::vector<TraceRun> runs;
    for (std::size_t i = 0; i < configs.size() && i < traced.size(); ++i)
      runs.push_back({configs[i].label(), traced[i], {{"config", configs[i].label()}}});
    if (auto w = writeChromeTrace(o.trace.string(), runs, settings); !w) return w.error();
  }
  markParetoFront(report.runs);

  // The strips: the reference and each Lakhia budget, over their FLIP heat maps.
  std::vector<double> budgets;
  for (const auto& [key, m] : stripCells)
    if (std::find(budgets.begin(), budgets.end(), key.second) == budgets.end())
      budgets.push_back(key.second);
  std::sort(budgets.begin(), budgets.end());
  for (std::size_t k : stripAt) {
    std::vector<hlod::Image> cells;
    cells.push_back(refImages[k]);
    for (double b : budgets) cells.push_back(stripCells[{k, b}].image);
    cells.push_back({});
    for (double b : budgets) {
      const Measured& m = stripCells[{k, b}];
      cells.push_back(hlod::metrics::errorHeatMap(m.flipMap, m.image.width, m.image.height));
    }
    cells.push_back({});
    for (double b : budgets) {
      const Measured& m = stripCells[{k, b}];
      auto map = hlod::metrics::coverageMap(m.image, refMasks[k], m.coverage);
      if (!map) return map.error();
      cells.push_back(std::move(*map));
    }
    const int cw = std::min(o.width, 320), ch = std::max(1, cw * o.height / o.width);
    const hlod::Image grid = composeGrid(cells, int(budgets.size()) + 1, cw, ch);
    auto png = renderer::encodePng(grid);
    if (!png) return png.error();
    const std::string name = "strip-" + std::to_string(frames[k]) + ".png";
    if (auto w = renderer::writeBytes((outDir / name).string(), *png); !w) return w.error();
    report.strips.push_back(name);
    std::string caption = "Frame " + std::to_string(frames[k]) +
                          " (t = " + std::to_string(report.reference[k].time).substr(0, 5) +
                          " s). Top: full detail, then Lakhia at";
    for (double b : budgets) caption += " " + std::to_string(int(b)) + " ms";
    caption +=
        ". Middle: FLIP error against full detail (black none, yellow most). Bottom: "
        "where the silhouettes differ (red: a hole, sky where full detail has geometry; "
        "cyan: a shard).";
    report.stripCaptions.push_back(caption);
  }
  if (auto w = writeStudyReport(outDir, report); !w) return w.error();
  return report;
}

}  // namespace service
