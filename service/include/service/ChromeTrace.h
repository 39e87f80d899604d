#pragma once
// A run's per-frame timing as Chrome Trace Event JSON, for Perfetto UI (ui.perfetto.dev) and
// chrome://tracing. Format: "Trace Event Format" (Google, the document linked from
// catapult/docs/trace-event-format.md): the JSON Object Format,
//   {"traceEvents": [...], "displayTimeUnit": "ms", "otherData": {...}},
// with Complete events ("ph":"X", ts and dur in microseconds), Counter events ("ph":"C", numeric
// args, one series per arg) and Metadata events ("ph":"M", process_name / thread_name).
//
// Each run is a process (pid 1, 2, ... in the order given, named by TraceRun::name) with one
// thread (tid 1, "frames"). Per frame, a slice "frame N" from the start of renderFrame to the end
// of its readback and encode, holding, in time order:
//   select, upload (the frame's uploads: its first one's start, their summed time), draw (the
//   call that ran the passes, through glFinish), readback, encode (the sinks that take pixels);
//   draw holds the passes that ran (refine, shadow, geometry, occlusion, sky, ssao, ssao-blur,
//   composite, outline), in the renderer's order.
// Where they start: the frame's steps at the times FrameTimeline recorded where they ran (the
// frame driver's steady clock; ts 0 is the first frame's start of all runs). The passes are
// known only as GPU durations (GL_TIME_ELAPSED; on llvmpipe, CPU time): they are laid end to end
// from the draw's start, an estimate of where they ran inside it, not a measurement.
// Perfetto and chrome://tracing need the slices of a thread to nest strictly: each child is kept
// inside its parent and after its previous sibling, cut where a measurement would overflow;
// otherData.clippedSlices counts the slices cut. A frame without a timeline (all zero: records
// from elsewhere) is laid out end to end after the previous frame, children in order from its
// start (otherData.framesWithoutTimeline counts them).
// Counters, at each frame's end: "resident bytes" {bytes, capBytes}, "gpu bytes" {bytes},
// "v_time" {msPerCost}, "frame time" {gpuMs, targetMs}.
// otherData: what `otherData` the caller gives, plus "runs" ([{pid, name, settings}]),
// "clippedSlices", "framesWithoutTimeline" and "passPlacement" (the sentence above, for a reader).
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hlod/Result.h"
#include "hlod/runtime/FrameStats.h"
#include "hlod/runtime/PathRun.h"

namespace service {

// One run of frames: a process of the trace.
struct TraceRun {
  std::string name;
  std::span<const hlod::FrameRecord> frames;
  nlohmann::json settings = nlohmann::json::object();
};

nlohmann::json chromeTrace(std::span<const TraceRun> runs,
                           const nlohmann::json& otherData = nlohmann::json::object());
hlod::Status writeChromeTrace(const std::string& path, std::span<const TraceRun> runs,
                              const nlohmann::json& otherData = nlohmann::json::object());

// Keeps a path run's records and writes its trace (one run) to `path` in finish(), also after a
// cancel or an error: the frames so far. Goes after the sinks that take pixels (runPath runs
// those first), so that each record it sees has its readback and encode.
class ChromeTraceSink final : public hlod::FrameSink {
 public:
  ChromeTraceSink(std::string path, std::string name, nlohmann::json settings);
  hlod::Status onFrame(const hlod::FrameRecord& record, const hlod::Image* pixels) override;
  hlod::Status finish() override;

 private:
  std::string path_, name_;
  nlohmann::json settings_;
  std::vector<hlod::FrameRecord> frames_;
};

}  // namespace service
