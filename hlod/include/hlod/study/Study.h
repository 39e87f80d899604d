#pragma once
// The accuracy study (what accuracy costs in time): for frames of a camera path, the image of
// each selector at each budget (and each SSE threshold) against the full-detail reference, with
// its frame time. This header holds the study's data, its summary and its answers; the runner
// that renders is service/src/study/StudyRunner.cpp, the report is StudyReport.h.
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/runtime/Camera.h"
#include "hlod/runtime/FrameDriver.h"
#include "hlod/store/Skeleton.h"

namespace hlod::study {

// PSNR of identical images is infinite; summaries and files cap it here (dB).
constexpr double kMaxPsnr = 100.0;
// A frame whose coverage differs from the reference's by more than this share of the pixels
// shows holes or shards.
constexpr double kCoverageLimit = 0.005;

struct StudyConfig {
  std::string selector;   // "lakhia", "sse", "fs"
  double budgetMs = 0.0;  // the frame budget (what sse ignores)
  double ssePx = 0.0;     // sse: the pixel threshold
  FrameMode mode = FrameMode::Settled;
  std::string label() const;  // "lakhia 33 ms", "sse 4 px", "... realtime"
};

// One studied frame of one configuration, measured against the reference frame.
struct FrameResult {
  std::uint64_t frame = 0;  // index of the frame on the path at the study's fps
  double time = 0.0;        // path time, s
  double frameMs = 0.0;     // frame time: GL work through glFinish (uploads included)
  double queryGpuMs = 0.0;  // the passes' GPU timer queries
  std::uint64_t triangles = 0;
  double psnr = 0.0;              // dB against the reference, capped at kMaxPsnr
  double ssim = 0.0;              // mean SSIM on luma
  double flip = 0.0;              // mean LDR-FLIP
  double coverage = 0.0;          // share of pixels background in exactly one of the two images
  double sseMaxPx = 0.0;          // screen-space geometric error of the front, pixels: largest
  double sseMeanPx = 0.0;         // and mean over the front's nodes
  std::uint32_t toggles = 0;      // up + down toggles of this frame
  std::uint64_t bytesLoaded = 0;  // payload bytes read since the configuration's previous frame
};

struct RunSummary {
  std::size_t frames = 0;
  double meanMs = 0.0, p95Ms = 0.0, maxMs = 0.0;
  double meanTriangles = 0.0;
  double medianPsnr = 0.0, meanPsnr = 0.0, worstPsnr = 0.0;
  std::uint64_t worstFrame = 0;  // path frame of the worst PSNR
  double meanSsim = 0.0, meanFlip = 0.0;
  double maxCoverage = 0.0;
  std::size_t framesOverCoverage = 0;  // frames above kCoverageLimit
  double meanSseMaxPx = 0.0;
  double togglesPerFrame = 0.0;
  std::uint64_t bytesLoaded = 0;
};

RunSummary summarize(std::span<const FrameResult> frames);

struct Run {
  StudyConfig config;
  std::vector<FrameResult> frames;
  RunSummary summary;
  bool onParetoFront = false;  // of all runs by (mean frame ms, median PSNR)
};

// The reference: the full-detail frames (the `full` selector, settled).
struct ReferenceFrame {
  std::uint64_t frame = 0;
  double time = 0.0;
  double frameMs = 0.0;
  std::uint64_t triangles = 0;
};

// Marks the runs on the Pareto front of (mean frame ms lower, median PSNR higher).
void markParetoFront(std::vector<Run>& runs);

// The screen-space geometric error of a front (pixels): each node's geometricError projected at
// its distance from the camera, as the SSE selector measures it.
struct FrontError {
  double maxPx = 0.0, meanPx = 0.0;
};
FrontError frontScreenError(const Skeleton& skeleton, const View& view,
                            std::span<const std::uint32_t> front);

// What the study answers, for the report and the README.
struct Answers {
  // At Lakhia's mean frame time, SSE's median PSNR interpolated along its thresholds: the
  // difference (Lakhia - SSE, dB) per Lakhia budget; NaN where SSE's range does not reach.
  struct AtEqualTime {
    double budgetMs = 0.0, lakhiaMs = 0.0, lakhiaPsnr = 0.0, ssePsnr = 0.0, gainDb = 0.0;
    bool lakhiaDominatedBySse = false;  // some SSE run is faster and better
  };
  std::vector<AtEqualTime> lakhiaVsSse;
  // Between consecutive budgets of a selector: dB of median PSNR per extra ms of mean time.
  struct Slope {
    std::string selector;
    double fromBudget = 0.0, toBudget = 0.0, fromMs = 0.0, toMs = 0.0, dbPerMs = 0.0;
  };
  std::vector<Slope> dbPerMs;
  // Lakhia at the budget nearest 33 ms.
  double lakhia33Budget = 0.0, lakhia33MedianPsnr = 0.0, lakhia33WorstPsnr = 0.0;
  std::uint64_t lakhia33WorstFrame = 0;
  double lakhia33MaxCoverage = 0.0;
  std::size_t lakhia33FramesOverCoverage = 0;
  std::vector<std::string> lines() const;  // plain sentences
};
Answers answer(const std::vector<Run>& runs);

}  // namespace hlod::study
