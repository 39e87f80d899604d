#pragma once
// A path run split into N segments (`hlodr render --segment i/N`, `"segments": N` of a job):
// which frames segment i renders, the "i/N" argument, and the checks that joining the
// segments' stats needs (every frame once, in order, from runs of the same settings).
//
// Segment i of a run of F frames renders frames [floor(i*F/N), floor((i+1)*F/N)), numbered as in
// the whole run; before its first frame it renders up to W warm-up frames that are not written
// (PathRunOptions::warmupFrames), so that the selector, its hysteresis and the loader reach
// about the state the whole run has there (exactly, for a selector whose state is a function of
// the frames drawn: docs/cli.md, "Segments").
#include <cstdint>
#include <string>
#include <vector>

#include "hlod/Result.h"
#include "hlod/runtime/FrameStats.h"

namespace hlod {

inline constexpr std::uint32_t kMaxSegments = 1024;

struct FrameRange {
  std::uint64_t first = 0;  // the first frame
  std::uint64_t end = 0;    // one past the last
};

// The frames of segment `index` of `count` in a run of `total` frames; count > 0, index < count.
FrameRange segmentRange(std::uint64_t total, std::uint32_t index, std::uint32_t count);

struct SegmentSpec {
  std::uint32_t index = 0;
  std::uint32_t count = 1;
};

// "i/N" with 0 <= i < N <= kMaxSegments, both whole decimal numbers; anything else is an Error
// that says what is wrong.
Result<SegmentSpec> parseSegment(const std::string& text);

// One segment's output as its stats file describes it.
struct SegmentPart {
  std::string name;  // for messages: the file it came from
  SegmentSpec spec;
  FrameRange range;
  std::uint64_t runFrames = 0;  // of the whole run
  int width = 0, height = 0;
  double fps = 0.0;
  std::vector<FrameRecord> frames;
};

// The order in which the parts join into the whole run (by first frame), or an Error naming the
// problem: parts of different splits, sizes or frame rates, a segment missing or given twice, a
// gap or an overlap between ranges, or a part whose frames are not its range's.
Result<std::vector<std::size_t>> segmentOrder(const std::vector<SegmentPart>& parts);

}  // namespace hlod
