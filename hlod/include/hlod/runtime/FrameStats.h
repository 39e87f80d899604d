#pragma once
// Per-frame statistics of a path run and their summary: the figures of Lakhia sec. IV (HLODs
// drawn per level, up/down toggles, actual vs target frame time) plus loading and memory.
//
// stats.json: {"frames": [FrameRecord...], "summary": FrameSummary}. Field names and units:
//   frames[i]: index (frame number), time (s, path time), targetMs (budget, ms), estimatedMs
//     (the frame's uploads plus the selector's sum of timeNeeded, ms), gpuMs (frame time: GL work
//     through glFinish, uploads included, ms; the "actual" time compared with the target), cpuMs
//     (wall time of the whole frame, ms), selectorMs (front selection CPU time, ms), triangles,
//     nodesPerLevel (array, index = level), upToggles, downToggles, vTime (ms per unit of cost),
//     residentBytes, capBytes (0 = none), loadsStarted, loadsFinished, unloads (cumulative counts),
//     coarserNotResident (nodes drawn coarser because a visible child was not resident), stalls
//     (frames or waits the renderer counted as a stall, e.g. settled-mode waits), uploadMs
//     (GPU uploads in this frame, ms), drawMs (the drawing through glFinish, ms), queryGpuMs (the
//     passes' GL_TIME_ELAPSED sum, ms), shadowMs, geometryMs, skyMs, ssaoMs, ssaoBlurMs,
//     compositeMs, outlineMs (each pass's GL_TIME_ELAPSED, ms; 0 for a pass the scene does not
//     declare, which does not run), uploads, uploadBytes, pendingUploads (loaded, waiting for
//     an upload), loadErrors and bytesRead (cumulative, of the loader), cacheHits (cumulative:
//     nodes another session had decoded already), partialNodes (front nodes drawn with fewer
//     triangles than their own, from their progression), splatNodes and splats (front nodes drawn
//     as splats, and their splats), cellNodes (front nodes that are cell nodes, Skeleton.h),
//     occlusionMs (the occlusion queries' box pass, GL_TIME_ELAPSED, ms), occlusion (1 when
//     occlusion culling ran this frame), occlusionQueries (queries issued: on draws and on box
//     batches), occludedNodes and occludedTriangles (nodes in the frustum left out with their
//     subtrees because a query found them hidden, and their own triangles), listIn and listOut
//     (settled frames: front nodes resident when the frame began, L_I, and those it waited for,
//     L_O; Manocha 5.5), gpuBytes (bytes of the session's GPU copies after the frame),
//     gpuEvictions (GPU copies freed this frame by the GPU memory budget), wallMs (the frame's
//     whole wall time, waits for the loader and uploads included, ms);
//     view-dependent rendering (`--selector vdr`): refineMs (the frame's refinement and the
//     rebuilding and upload of its changed clusters' arrays, CPU ms, part of gpuMs),
//     vertexSplits and edgeCollapses (this frame's; forced splits included), activeClusters (on
//     the active cluster lists), errorBoundPx (the bound the frame was refined to, pixels).
//   summary: frames, medianRelError and p95RelError (of |gpuMs - targetMs| / targetMs),
//     shareOverTarget and shareOver125 (fraction of frames with gpuMs > target, > 1.25 target),
//     p99OverTarget (p99 of gpuMs / targetMs), meanGpuMs, totalStalls, peakResidentBytes,
//     capBytes, peakOverCap (peak / cap, 0 when no cap), togglesPerFrame ((up+down)/frames),
//     totalUpToggles, totalDownToggles, meanTriangles (triangles drawn per frame),
//     coarserPerFrame (mean coarserNotResident: detail missing because it was not loaded),
//     occludedPerFrame (mean occludedNodes), occlusionFrames (frames with culling on),
//     peakGpuBytes.
// stats.csv: one row per frame with the same names; nodesPerLevel as columns level0, level1...
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hlod/Result.h"

namespace hlod {

struct Selection;
struct LoaderCounters;

// When the frame's steps ran, for a timeline (the Chrome trace, service/ChromeTrace.h); not part
// of stats.json or stats.csv. Times are microseconds on the frame driver's clock (the loader's
// LinkClock: the steady clock outside tests), whose epoch means nothing: only differences do.
// A step that did not run has its duration 0. The frame driver sets the first four; the path run
// (PathRun.h) the readback and the encode (the sinks that take pixels), after the frame.
struct FrameTimeline {
  double startUs = 0.0;        // the frame began (renderFrame was called)
  double uploadStartUs = 0.0;  // this frame's first upload (its sum is FrameRecord::uploadMs)
  double selectStartUs = 0.0;  // front selection (FrameRecord::selectorMs)
  double drawStartUs = 0.0;    // the draw call that ran the passes, through glFinish
  double drawEndUs = 0.0;
  double readbackStartUs = 0.0, readbackUs = 0.0;
  double encodeStartUs = 0.0, encodeUs = 0.0;
};

struct FrameRecord {
  std::uint64_t index = 0;
  double time = 0.0;
  double targetMs = 0.0;
  double estimatedMs = 0.0;
  double gpuMs = 0.0;
  double cpuMs = 0.0;
  double selectorMs = 0.0;
  std::uint64_t triangles = 0;
  std::vector<std::uint32_t> nodesPerLevel;
  std::uint32_t upToggles = 0;
  std::uint32_t downToggles = 0;
  double vTime = 0.0;
  std::uint64_t residentBytes = 0;
  std::uint64_t capBytes = 0;
  std::uint64_t loadsStarted = 0;
  std::uint64_t loadsFinished = 0;
  std::uint64_t unloads = 0;
  std::uint32_t coarserNotResident = 0;
  std::uint32_t stalls = 0;
  double uploadMs = 0.0;
  double drawMs = 0.0;
  double queryGpuMs = 0.0;
  double shadowMs = 0.0;
  double geometryMs = 0.0;
  double skyMs = 0.0;
  double ssaoMs = 0.0;
  double ssaoBlurMs = 0.0;
  double compositeMs = 0.0;
  double outlineMs = 0.0;
  std::uint32_t uploads = 0;
  std::uint64_t uploadBytes = 0;
  std::uint32_t pendingUploads = 0;
  std::uint64_t loadErrors = 0;
  std::uint64_t bytesRead = 0;
  std::uint64_t cacheHits = 0;
  std::uint32_t partialNodes = 0;  // front nodes drawn with fewer triangles (Parry's arrays)
  std::uint32_t splatNodes = 0;    // front nodes drawn as splats
  std::uint64_t splats = 0;
  std::uint32_t cellNodes = 0;  // front nodes that are cell nodes
  double occlusionMs = 0.0;
  bool occlusion = false;
  std::uint32_t occlusionQueries = 0;
  std::uint32_t occludedNodes = 0;
  std::uint64_t occludedTriangles = 0;
  std::uint32_t listIn = 0;
  std::uint32_t listOut = 0;
  std::uint64_t gpuBytes = 0;
  std::uint32_t gpuEvictions = 0;
  double wallMs = 0.0;
  double refineMs = 0.0;  // view-dependent rendering: refinement and cluster arrays, ms
  std::uint32_t vertexSplits = 0;
  std::uint32_t edgeCollapses = 0;
  std::uint32_t activeClusters = 0;
  double errorBoundPx = 0.0;
  FrameTimeline timeline;  // when the steps ran (not in stats.json / stats.csv)
};

// Copies the selector's part (targetMs, estimatedMs, triangles, levels, toggles, vTime, ...).
void fillFromSelection(FrameRecord& record, const Selection& selection);
// Sets the per-pass field of the pass named `pass` ("shadow", "geometry", "sky", "ssao",
// "ssao-blur", "composite", "outline", "occlusion", "refine"); false for another name.
bool setPassMs(FrameRecord& record, const std::string& pass, double ms);
// A pass whose cost is not per triangle of the front, which the budget reserves (last frame's)
// and v_time leaves out: the per-pixel passes (sky, ssao, ssao-blur, composite, outline), and
// view-dependent rendering's refine (its cost follows the view's motion); shadow and geometry
// draw the front.
bool isScreenPass(const std::string& pass);
// Copies the loader's part (residentBytes, capBytes, load/unload counts).
void fillFromLoader(FrameRecord& record, const LoaderCounters& counters);

struct FrameSummary {
  std::uint64_t frames = 0;
  double medianRelError = 0.0;
  double p95RelError = 0.0;
  double shareOverTarget = 0.0;
  double shareOver125 = 0.0;
  double p99OverTarget = 0.0;
  double meanGpuMs = 0.0;
  std::uint64_t totalStalls = 0;
  std::uint64_t peakResidentBytes = 0;
  std::uint64_t capBytes = 0;
  double peakOverCap = 0.0;
  double togglesPerFrame = 0.0;
  std::uint64_t totalUpToggles = 0;
  std::uint64_t totalDownToggles = 0;
  double meanTriangles = 0.0;
  double coarserPerFrame = 0.0;
  double occludedPerFrame = 0.0;
  std::uint64_t occlusionFrames = 0;
  std::uint64_t peakGpuBytes = 0;
};

// Frames with targetMs <= 0 are left out of the error figures.
FrameSummary summarize(std::span<const FrameRecord> frames);

// One frame as a single line of JSON (the stats.json frame object): for event streams and headers.
std::string frameJson(const FrameRecord& frame);
std::string summaryJson(const FrameSummary& summary);
// extra: a JSON object merged in at the top level (e.g. the run's settings), or "".
std::string statsJson(std::span<const FrameRecord> frames, const FrameSummary& summary,
                      const std::string& extra = "");
std::string statsCsv(std::span<const FrameRecord> frames);
// The frames of a stats.json text (its "frames" array, every field of FrameRecord read back as
// statsJson wrote it; a field missing stays at its default), or an Error for text that is not
// such a file.
Result<std::vector<FrameRecord>> parseStatsFrames(const std::string& statsJsonText);
Status writeStatsJson(const std::string& path, std::span<const FrameRecord> frames,
                      const FrameSummary& summary, const std::string& extra = "");
Status writeStatsCsv(const std::string& path, std::span<const FrameRecord> frames);

}  // namespace hlod
