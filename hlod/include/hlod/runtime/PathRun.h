#pragma once
// A camera path run: a loop over the path's frames that hands each one to sinks (a PNG
// sequence, an MP4, the stats files, an HTTP event stream), with a cancel flag and a per-frame
// callback. The library never prints: progress goes to the callback.
#include <atomic>
#include <cstdint>
#include <functional>
#include <span>
#include <string>

#include "hlod/runtime/CameraPath.h"
#include "hlod/runtime/FrameDriver.h"
#include "hlod/runtime/FrameStats.h"
#include "hlod/runtime/Segments.h"

namespace hlod {

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // Whether onFrame needs the frame's pixels (a readback costs time: only when some sink does).
  virtual bool wantsPixels() const { return false; }
  // After each frame; pixels is the frame's image when wantsPixels(), else null. An Error ends
  // the run (a full disk, a video encoder that died).
  virtual Status onFrame(const FrameRecord& record, const Image* pixels) = 0;
  // Once after the last frame, also after a cancel or an error, so that what was written is
  // complete (a video closed, the stats of the frames so far).
  virtual Status finish() = 0;
};

struct PathRunOptions {
  double fps = 30.0;
  long long maxFrames = -1;      // render only the first N frames; < 0: all
  double prefetchSeconds = 0.0;  // > 0: prefetch the selection this far ahead on the path
  FrameMode mode = FrameMode::Realtime;
  // A segment of the run (`--segment i/N`): of the F frames (after maxFrames), only frames
  // [i*F/N, (i+1)*F/N) go to the sinks, numbered as in the whole run. Before the first one, up
  // to warmupFrames earlier frames are rendered for the selector's, the hysteresis' and the
  // loader's state only (no sink, no callback). segmentCount 1: the whole run, no warm-up.
  static constexpr std::uint64_t kDefaultWarmupFrames = 60;
  std::uint32_t segmentIndex = 0;
  std::uint32_t segmentCount = 1;
  std::uint64_t warmupFrames = kDefaultWarmupFrames;
};

struct PathRunResult {
  std::uint64_t framesRendered = 0;  // of the segment (the whole run when not split)
  std::uint64_t framesTotal = 0;     // of the segment: end - first
  std::uint64_t firstFrame = 0;      // the segment's frames: [firstFrame, endFrame)
  std::uint64_t endFrame = 0;
  std::uint64_t runFrames = 0;     // of the whole run (path after maxFrames)
  std::uint64_t warmupFrames = 0;  // rendered before firstFrame, not written
  bool cancelled = false;
};

// Called after each frame with the frames done so far and the total.
using FrameCallback =
    std::function<void(const FrameRecord& record, std::uint64_t done, std::uint64_t total)>;

// The frames of the whole run: the path's at options.fps, at most options.maxFrames.
Result<std::uint64_t> runFrameCount(const CameraPath& path, const PathRunOptions& options);

// Runs the path's frames (or a segment's) through the driver. A set cancel flag stops the run after
// the current frame (result.cancelled). Every sink's finish() runs whatever happened; the first
// Error (frame, sink or finish) is returned.
Result<PathRunResult> runPath(FrameDriver& driver, const CameraPath& path,
                              const PathRunOptions& options, std::span<FrameSink* const> sinks,
                              const std::atomic<bool>* cancel = nullptr,
                              const FrameCallback& onFrame = {});

// Keeps every record of the run and writes stats.json (the FrameStats format, with `extra`, a
// JSON object, merged in at the top), stats.csv and, with plots, the three SVG figures of
// Lakhia IV (levels.svg, toggles.svg, frametime.svg) under `prefix` + name.
class StatsSink final : public FrameSink {
 public:
  StatsSink(std::string jsonPath, std::string csvPath, std::string plotPrefix = "",
            std::string extra = "");
  Status onFrame(const FrameRecord& record, const Image* pixels) override;
  Status finish() override;
  const std::vector<FrameRecord>& frames() const { return frames_; }
  std::vector<std::string> plotPaths() const;

 private:
  std::string jsonPath_, csvPath_, plotPrefix_, extra_;
  std::vector<FrameRecord> frames_;
};

}  // namespace hlod
