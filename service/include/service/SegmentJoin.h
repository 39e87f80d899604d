#pragma once
// Joins the outputs of a path run's segments (`hlodr render --segment i/N`) into what the
// unsplit run writes: one MP4 (ffmpeg's concat demuxer, no re-encode) or one folder of PNGs,
// and one stats.json / stats.csv whose frames run on without a gap and whose summary is
// recomputed from all of them. The parts are checked first (hlod::segmentOrder): a missing
// segment, a gap, an overlap or parts of different sizes or frame rates are refused, and nothing
// is written then.
#include <filesystem>
#include <vector>

#include "hlod/Result.h"
#include "hlod/runtime/FrameStats.h"

namespace service {

struct JoinResult {
  std::uint64_t frames = 0;
  std::uint32_t segments = 0;
  hlod::FrameSummary summary;
  std::filesystem::path statsJson, statsCsv;
};

// parts: each an .mp4 (with STEM.stats.json beside it) or a folder (frame_NNNNN.png and
// stats.json), in any order; output: an .mp4 for .mp4 parts, a folder for folder parts.
hlod::Result<JoinResult> joinSegments(const std::vector<std::filesystem::path>& parts,
                                      const std::filesystem::path& output);

// The .mp4 files one after the other in `output`, by ffmpeg's concat demuxer without
// re-encoding (they must share size, rate and encoder settings, as a split run's parts do).
hlod::Status concatVideos(const std::vector<std::filesystem::path>& parts,
                          const std::filesystem::path& output);

}  // namespace service
