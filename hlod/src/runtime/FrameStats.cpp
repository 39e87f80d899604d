#include "hlod/runtime/FrameStats.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hlod/AtomicFile.h"
#include "hlod/runtime/Loader.h"
#include "hlod/runtime/Selector.h"

namespace hlod {

namespace {

// Nearest-rank percentile of a sorted list (q in [0, 1]).
double percentile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  const double rank = std::ceil(q * static_cast<double>(sorted.size()));
  const std::size_t i = static_cast<std::size_t>(std::clamp(rank, 1.0, double(sorted.size()))) - 1;
  return sorted[i];
}

double finiteOrZero(double v) {
  return std::isfinite(v) ? v : 0.0;
}

Status writeText(const std::string& path, const std::string& text) {
  return writeFileAtomically(path, text);  // a full disk leaves no empty stats.json
}

}  // namespace

void fillFromSelection(FrameRecord& r, const Selection& s) {
  r.targetMs = s.targetMs;
  r.estimatedMs = s.estimatedMs;
  r.triangles = s.triangles;
  r.nodesPerLevel = s.nodesDrawnPerLevel;
  r.upToggles = s.upToggles;
  r.downToggles = s.downToggles;
  r.vTime = s.vTime;
  r.coarserNotResident = s.coarserBecauseNotResident;
  r.partialNodes = s.partialNodes;
  r.splatNodes = s.splatNodes;
  r.splats = s.splats;
  r.cellNodes = s.cellsDrawn;
  r.occludedNodes = static_cast<std::uint32_t>(s.occluded.size());
  r.occludedTriangles = s.occludedTriangles;
  r.vertexSplits = s.vertexSplits;
  r.edgeCollapses = s.edgeCollapses;
  r.activeClusters = s.activeClusters;
  r.errorBoundPx = s.errorBoundPx;
}

bool setPassMs(FrameRecord& r, const std::string& pass, double ms) {
  static const std::pair<const char*, double FrameRecord::*> kPasses[] = {
      {"shadow", &FrameRecord::shadowMs},
      {"geometry", &FrameRecord::geometryMs},
      {"sky", &FrameRecord::skyMs},
      {"ssao", &FrameRecord::ssaoMs},
      {"ssao-blur", &FrameRecord::ssaoBlurMs},
      {"composite", &FrameRecord::compositeMs},
      {"outline", &FrameRecord::outlineMs},
      {"occlusion", &FrameRecord::occlusionMs},
      {"refine", &FrameRecord::refineMs}};
  for (const auto& [name, field] : kPasses)
    if (pass == name) {
      r.*field = ms;
      return true;
    }
  return false;
}

bool isScreenPass(const std::string& pass) {
  return pass == "sky" || pass == "ssao" || pass == "ssao-blur" || pass == "composite" ||
         pass == "outline" || pass == "refine";
}

void fillFromLoader(FrameRecord& r, const LoaderCounters& c) {
  r.residentBytes = c.residentBytes;
  r.capBytes = c.capBytes;
  r.loadsStarted = c.loadsStarted;
  r.loadsFinished = c.loadsFinished;
  r.unloads = c.unloads;
  r.loadErrors = c.loadErrors;
  r.bytesRead = c.bytesRead;
  r.cacheHits = c.cacheHits;
}

FrameSummary summarize(std::span<const FrameRecord> frames) {
  FrameSummary s;
  s.frames = frames.size();
  std::vector<double> rel, ratio;
  std::size_t over = 0, over125 = 0;
  double sumGpu = 0.0, sumTriangles = 0.0, sumCoarser = 0.0, sumOccluded = 0.0;
  for (const FrameRecord& f : frames) {
    sumGpu += finiteOrZero(f.gpuMs);
    sumTriangles += static_cast<double>(f.triangles);
    sumCoarser += f.coarserNotResident;
    sumOccluded += f.occludedNodes;
    s.occlusionFrames += f.occlusion;
    s.peakGpuBytes = std::max(s.peakGpuBytes, f.gpuBytes);
    s.totalStalls += f.stalls;
    s.totalUpToggles += f.upToggles;
    s.totalDownToggles += f.downToggles;
    s.peakResidentBytes = std::max(s.peakResidentBytes, f.residentBytes);
    s.capBytes = std::max(s.capBytes, f.capBytes);
    if (!(f.targetMs > 0.0) || !std::isfinite(f.gpuMs)) continue;
    rel.push_back(std::abs(f.gpuMs - f.targetMs) / f.targetMs);
    ratio.push_back(f.gpuMs / f.targetMs);
    over += f.gpuMs > f.targetMs;
    over125 += f.gpuMs > 1.25 * f.targetMs;
  }
  std::sort(rel.begin(), rel.end());
  std::sort(ratio.begin(), ratio.end());
  s.medianRelError = percentile(rel, 0.5);
  s.p95RelError = percentile(rel, 0.95);
  s.p99OverTarget = percentile(ratio, 0.99);
  if (!rel.empty()) {
    s.shareOverTarget = static_cast<double>(over) / rel.size();
    s.shareOver125 = static_cast<double>(over125) / rel.size();
  }
  if (!frames.empty()) {
    s.meanGpuMs = sumGpu / frames.size();
    s.togglesPerFrame = static_cast<double>(s.totalUpToggles + s.totalDownToggles) / frames.size();
    s.meanTriangles = sumTriangles / frames.size();
    s.coarserPerFrame = sumCoarser / frames.size();
    s.occludedPerFrame = sumOccluded / frames.size();
  }
  s.peakOverCap = s.capBytes > 0 ? double(s.peakResidentBytes) / double(s.capBytes) : 0.0;
  return s;
}

namespace {

using OrderedJson = nlohmann::ordered_json;

// The one list of a frame's fields, in stats.json and stats.csv order (nodesPerLevel last: the
// CSV spreads it over level0, level1, ... columns).
OrderedJson frameObject(const FrameRecord& f) {
  return {{"index", f.index},
          {"time", finiteOrZero(f.time)},
          {"targetMs", finiteOrZero(f.targetMs)},
          {"estimatedMs", finiteOrZero(f.estimatedMs)},
          {"gpuMs", finiteOrZero(f.gpuMs)},
          {"cpuMs", finiteOrZero(f.cpuMs)},
          {"selectorMs", finiteOrZero(f.selectorMs)},
          {"uploadMs", finiteOrZero(f.uploadMs)},
          {"drawMs", finiteOrZero(f.drawMs)},
          {"queryGpuMs", finiteOrZero(f.queryGpuMs)},
          {"shadowMs", finiteOrZero(f.shadowMs)},
          {"geometryMs", finiteOrZero(f.geometryMs)},
          {"skyMs", finiteOrZero(f.skyMs)},
          {"ssaoMs", finiteOrZero(f.ssaoMs)},
          {"ssaoBlurMs", finiteOrZero(f.ssaoBlurMs)},
          {"compositeMs", finiteOrZero(f.compositeMs)},
          {"outlineMs", finiteOrZero(f.outlineMs)},
          {"triangles", f.triangles},
          {"upToggles", f.upToggles},
          {"downToggles", f.downToggles},
          {"vTime", finiteOrZero(f.vTime)},
          {"residentBytes", f.residentBytes},
          {"capBytes", f.capBytes},
          {"loadsStarted", f.loadsStarted},
          {"loadsFinished", f.loadsFinished},
          {"unloads", f.unloads},
          {"loadErrors", f.loadErrors},
          {"bytesRead", f.bytesRead},
          {"cacheHits", f.cacheHits},
          {"uploads", f.uploads},
          {"uploadBytes", f.uploadBytes},
          {"pendingUploads", f.pendingUploads},
          {"coarserNotResident", f.coarserNotResident},
          {"stalls", f.stalls},
          {"partialNodes", f.partialNodes},
          {"splatNodes", f.splatNodes},
          {"splats", f.splats},
          {"cellNodes", f.cellNodes},
          {"occlusionMs", finiteOrZero(f.occlusionMs)},
          {"occlusion", f.occlusion ? 1 : 0},
          {"occlusionQueries", f.occlusionQueries},
          {"occludedNodes", f.occludedNodes},
          {"occludedTriangles", f.occludedTriangles},
          {"listIn", f.listIn},
          {"listOut", f.listOut},
          {"gpuBytes", f.gpuBytes},
          {"gpuEvictions", f.gpuEvictions},
          {"wallMs", finiteOrZero(f.wallMs)},
          {"refineMs", finiteOrZero(f.refineMs)},
          {"vertexSplits", f.vertexSplits},
          {"edgeCollapses", f.edgeCollapses},
          {"activeClusters", f.activeClusters},
          {"errorBoundPx", finiteOrZero(f.errorBoundPx)},
          {"nodesPerLevel", f.nodesPerLevel}};
}

OrderedJson summaryObject(const FrameSummary& s) {
  return {{"frames", s.frames},
          {"medianRelError", s.medianRelError},
          {"p95RelError", s.p95RelError},
          {"shareOverTarget", s.shareOverTarget},
          {"shareOver125", s.shareOver125},
          {"p99OverTarget", s.p99OverTarget},
          {"meanGpuMs", s.meanGpuMs},
          {"totalStalls", s.totalStalls},
          {"peakResidentBytes", s.peakResidentBytes},
          {"capBytes", s.capBytes},
          {"peakOverCap", s.peakOverCap},
          {"togglesPerFrame", s.togglesPerFrame},
          {"totalUpToggles", s.totalUpToggles},
          {"totalDownToggles", s.totalDownToggles},
          {"meanTriangles", s.meanTriangles},
          {"coarserPerFrame", s.coarserPerFrame},
          {"occludedPerFrame", s.occludedPerFrame},
          {"occlusionFrames", s.occlusionFrames},
          {"peakGpuBytes", s.peakGpuBytes}};
}

}  // namespace

std::string frameJson(const FrameRecord& frame) {
  return frameObject(frame).dump();
}

std::string summaryJson(const FrameSummary& summary) {
  return summaryObject(summary).dump();
}

std::string statsJson(std::span<const FrameRecord> frames, const FrameSummary& s,
                      const std::string& extra) {
  OrderedJson list = OrderedJson::array();
  for (const FrameRecord& f : frames) list.push_back(frameObject(f));
  OrderedJson out = {{"frames", std::move(list)}, {"summary", summaryObject(s)}};
  if (!extra.empty()) {
    auto more = OrderedJson::parse(extra, nullptr, false);
    assert(more.is_object() && "statsJson: extra must be a JSON object");
    if (more.is_object())
      for (auto it = more.begin(); it != more.end(); ++it) out[it.key()] = it.value();
  }
  return out.dump(1);
}

std::string statsCsv(std::span<const FrameRecord> frames) {
  std::size_t levels = 0;
  for (const FrameRecord& f : frames) levels = std::max(levels, f.nodesPerLevel.size());
  std::ostringstream out;
  // Columns and values from the same frame object, nodesPerLevel spread over levelN columns.
  auto row = [&](const OrderedJson& object, bool header) {
    bool first = true;
    for (auto it = object.begin(); it != object.end(); ++it) {
      if (it.key() == "nodesPerLevel") continue;
      out << (first ? "" : ",") << (header ? it.key() : it.value().dump());
      first = false;
    }
  };
  row(frameObject(FrameRecord{}), true);
  for (std::size_t l = 0; l < levels; ++l) out << ",level" << l;
  out << '\n';
  for (const FrameRecord& f : frames) {
    row(frameObject(f), false);
    for (std::size_t l = 0; l < levels; ++l)
      out << ',' << (l < f.nodesPerLevel.size() ? f.nodesPerLevel[l] : 0u);
    out << '\n';
  }
  return out.str();
}

Status writeStatsJson(const std::string& path, std::span<const FrameRecord> frames,
                      const FrameSummary& summary, const std::string& extra) {
  return writeText(path, statsJson(frames, summary, extra) + "\n");
}

Status writeStatsCsv(const std::string& path, std::span<const FrameRecord> frames) {
  return writeText(path, statsCsv(frames));
}

}  // namespace hlod
