// A camera path run through a FrameDriver, frame by frame into sinks. See hlod/runtime/PathRun.h.
#include "hlod/runtime/PathRun.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hlod/runtime/LinkClock.h"
#include "hlod/runtime/Plots.h"

namespace hlod {

Result<std::uint64_t> runFrameCount(const CameraPath& path, const PathRunOptions& options) {
  if (!(options.fps > 0.0) || options.fps > 1000.0) return makeError("fps must be in (0, 1000]");
  auto all = path.frameCount(options.fps, options.maxFrames >= 0
                                              ? std::numeric_limits<std::uint64_t>::max()
                                              : kMaxPathFrames);
  if (!all) return all.error();
  if (options.maxFrames >= 0) return std::min<std::uint64_t>(*all, options.maxFrames);
  return *all;
}

Result<PathRunResult> runPath(FrameDriver& driver, const CameraPath& path,
                              const PathRunOptions& options, std::span<FrameSink* const> sinks,
                              const std::atomic<bool>* cancel, const FrameCallback& onFrame) {
  if (!(options.fps > 0.0) || options.fps > 1000.0) return makeError("fps must be in (0, 1000]");
  // Counted before anything is allocated: a path of 1e300 s is an Error, not a size_t overflow.
  // With --frames, the path may be longer than the frame limit: only the first ones are drawn.
  auto all = path.frameCount(options.fps, options.maxFrames >= 0
                                              ? std::numeric_limits<std::uint64_t>::max()
                                              : kMaxPathFrames);
  if (!all) return all.error();
  if (options.segmentCount == 0 || options.segmentIndex >= options.segmentCount ||
      options.segmentCount > kMaxSegments)
    return makeError("segment " + std::to_string(options.segmentIndex) + "/" +
                     std::to_string(options.segmentCount) +
                     ": need 0 <= i < N <= " + std::to_string(kMaxSegments));
  PathRunResult result;
  auto runFrames = runFrameCount(path, options);
  if (!runFrames) return runFrames.error();
  result.runFrames = *runFrames;
  if (options.segmentCount > result.runFrames && options.segmentCount > 1)
    return makeError("cannot split " + std::to_string(result.runFrames) + " frames into " +
                     std::to_string(options.segmentCount) + " segments");
  const FrameRange range =
      segmentRange(result.runFrames, options.segmentIndex, options.segmentCount);
  const bool split = options.segmentCount > 1;
  result.firstFrame = range.first;
  result.endFrame = range.end;
  result.framesTotal = range.end - range.first;
  result.warmupFrames = split ? std::min(options.warmupFrames, range.first) : 0;

  const FrameDriverOptions& fo = driver.options();
  const double aspect = static_cast<double>(fo.width) / fo.height;
  const bool pixels =
      std::any_of(sinks.begin(), sinks.end(), [](const FrameSink* s) { return s->wantsPixels(); });
  // Time from the frame index, not accumulated: frame i of a 24 h path is exactly i / fps.
  auto sampleOf = [&](std::uint64_t i) {
    const double t =
        std::min(path.startTime() + static_cast<double>(i) / options.fps, path.endTime());
    CameraSample s = path.sample(t, aspect);
    s.time = t;
    return s;
  };
  const std::uint64_t ahead =
      options.prefetchSeconds > 0.0
          ? static_cast<std::uint64_t>(std::llround(options.prefetchSeconds * options.fps))
          : 0;

  // Path frame i, with the camera `ahead` frames on for the prefetch.
  auto renderAt = [&](std::uint64_t i) {
    CameraSample look;
    if (ahead > 0) look = sampleOf(std::min(i + ahead, *all - 1));
    return driver.renderFrame(sampleOf(i), options.mode, ahead > 0 ? &look : nullptr);
  };
  Status failure = Ok{};
  // The warm-up: the frames before the segment, drawn as the whole run draws them, so that the
  // selector's state (v_time, hysteresis counters, last front) and the residency arrive at the
  // segment's first frame as they would; nothing of them is written.
  for (std::uint64_t i = range.first - result.warmupFrames; i < range.first; ++i) {
    if (cancel && cancel->load()) {
      result.cancelled = true;
      break;
    }
    auto rec = renderAt(i);
    if (!rec) {
      failure = makeError("warm-up frame " + std::to_string(i) + ": " + rec.message());
      break;
    }
  }
  for (std::uint64_t i = range.first; failure && !result.cancelled && i < range.end; ++i) {
    if (cancel && cancel->load()) {
      result.cancelled = true;
      break;
    }
    auto rec = renderAt(i);
    if (!rec) {
      failure = makeError("frame " + std::to_string(i) + ": " + rec.message());
      break;
    }
    // The whole run's frame number (the driver counts the warm-up's frames too).
    if (split) rec->index = i;
    // The timeline's readback and encode (the sinks that take pixels) are timed here, and the
    // sinks that take pixels go first, so that the others see the whole frame's timeline.
    LinkClock& clock = driver.loader().clock();
    Image image;
    if (pixels) {
      const auto start = clock.now();
      image = driver.renderer().readback();
      rec->timeline.readbackStartUs = microsecondsOf(start);
      rec->timeline.readbackUs = microsecondsOf(clock.now()) - rec->timeline.readbackStartUs;
    }
    for (const bool withPixels : {true, false}) {
      const auto start = clock.now();
      for (FrameSink* sink : sinks) {
        if (sink->wantsPixels() != withPixels) continue;
        const Image* mine = withPixels ? &image : nullptr;
        if (auto s = sink->onFrame(*rec, mine); !s && failure) failure = s;
      }
      if (withPixels && pixels) {
        rec->timeline.encodeStartUs = microsecondsOf(start);
        rec->timeline.encodeUs = microsecondsOf(clock.now()) - rec->timeline.encodeStartUs;
      }
    }
    if (!failure) break;
    ++result.framesRendered;
    if (onFrame) onFrame(*rec, result.framesRendered, result.framesTotal);
  }
  for (FrameSink* sink : sinks) {
    if (auto s = sink->finish(); !s && failure) failure = s;
  }
  if (!failure) return failure.error();
  return result;
}

StatsSink::StatsSink(std::string jsonPath, std::string csvPath, std::string plotPrefix,
                     std::string extra)
    : jsonPath_(std::move(jsonPath)),
      csvPath_(std::move(csvPath)),
      plotPrefix_(std::move(plotPrefix)),
      extra_(std::move(extra)) {}

Status StatsSink::onFrame(const FrameRecord& record, const Image*) {
  frames_.push_back(record);
  return Ok{};
}

std::vector<std::string> StatsSink::plotPaths() const {
  if (plotPrefix_.empty()) return {};
  return {plotPrefix_ + "levels.svg", plotPrefix_ + "toggles.svg", plotPrefix_ + "frametime.svg"};
}

Status StatsSink::finish() {
  if (auto s = writeStatsJson(jsonPath_, frames_, summarize(frames_), extra_); !s) return s;
  if (auto s = writeStatsCsv(csvPath_, frames_); !s) return s;
  if (plotPrefix_.empty()) return Ok{};
  const std::vector<std::string> paths = plotPaths();
  const std::string svgs[] = {levelsSvg(frames_), togglesSvg(frames_), frameTimeSvg(frames_)};
  for (std::size_t i = 0; i < paths.size(); ++i) {
    if (auto s = writeSvg(paths[i], svgs[i]); !s) return s;
  }
  return Ok{};
}

}  // namespace hlod
