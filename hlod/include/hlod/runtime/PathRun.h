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
};

struct PathRunResult {
  std::uint64_t framesRendered = 0;
  std::uint64_t framesTotal = 0;  // of the path (after maxFrames)
  bool cancelled = false;
};

// Called after each frame with the frames done so far and the total.
using FrameCallback =
    std::function<void(const FrameRecord& record, std::uint64_t done, std::uint64_t total)>;

// Runs the path's frames through the driver. A set cancel flag stops the run after the current
// frame (result.cancelled). Every sink's finish() runs whatever happened; the first Error
// (frame, sink or finish) is returned.
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
