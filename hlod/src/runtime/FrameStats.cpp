#include "hlod/runtime/FrameStats.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <type_traits>

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

namespace {

// Reads back what frameObject wrote: the same names, so that a field added there and not here
// shows in the round-trip test (FrameStatsTest), not as a silent zero in a joined run.
Status readFrameObject(const nlohmann::json& j, FrameRecord& f) {
  if (!j.is_object()) return makeError("a frame is not a JSON object");
  Status bad = Ok{};
  auto get = [&](const char* name, auto& field) {
    auto it = j.find(name);
    if (it == j.end() || !bad) return;
    using T = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<T, bool>) {
      if (it->is_number())
        field = it->template get<double>() != 0.0;
      else
        bad = makeError(std::string("frame field ") + name + " is not a number");
    } else if constexpr (std::is_floating_point_v<T>) {
      if (it->is_number())
        field = it->template get<double>();
      else
        bad = makeError(std::string("frame field ") + name + " is not a number");
    } else {
      if (it->is_number_unsigned() &&
          it->template get<std::uint64_t>() <= std::numeric_limits<T>::max())
        field = static_cast<T>(it->template get<std::uint64_t>());
      else
        bad = makeError(std::string("frame field ") + name + " is not a whole number in range");
    }
  };
  get("index", f.index);
  get("time", f.time);
  get("targetMs", f.targetMs);
  get("estimatedMs", f.estimatedMs);
  get("gpuMs", f.gpuMs);
  get("cpuMs", f.cpuMs);
  get("selectorMs", f.selectorMs);
  get("uploadMs", f.uploadMs);
  get("drawMs", f.drawMs);
  get("queryGpuMs", f.queryGpuMs);
  get("shadowMs", f.shadowMs);
  get("geometryMs", f.geometryMs);
  get("skyMs", f.skyMs);
  get("ssaoMs", f.ssaoMs);
  get("ssaoBlurMs", f.ssaoBlurMs);
  get("compositeMs", f.compositeMs);
  get("outlineMs", f.outlineMs);
  get("triangles", f.triangles);
  get("upToggles", f.upToggles);
  get("downToggles", f.downToggles);
  get("vTime", f.vTime);
  get("residentBytes", f.residentBytes);
  get("capBytes", f.capBytes);
  get("loadsStarted", f.loadsStarted);
  get("loadsFinished", f.loadsFinished);
  get("unloads", f.unloads);
  get("loadErrors", f.loadErrors);
  get("bytesRead", f.bytesRead);
  get("cacheHits", f.cacheHits);
  get("uploads", f.uploads);
  get("uploadBytes", f.uploadBytes);
  get("pendingUploads", f.pendingUploads);
  get("coarserNotResident", f.coarserNotResident);
  get("stalls", f.stalls);
  get("partialNodes", f.partialNodes);
  get("splatNodes", f.splatNodes);
  get("splats", f.splats);
  get("cellNodes", f.cellNodes);
  get("occlusionMs", f.occlusionMs);
  get("occlusion", f.occlusion);
  get("occlusionQueries", f.occlusionQueries);
  get("occludedNodes", f.occludedNodes);
  get("occludedTriangles", f.occludedTriangles);
  get("listIn", f.listIn);
  get("listOut", f.listOut);
  get("gpuBytes", f.gpuBytes);
  get("gpuEvictions", f.gpuEvictions);
  get("wallMs", f.wallMs);
  get("refineMs", f.refineMs);
  get("vertexSplits", f.vertexSplits);
  get("edgeCollapses", f.edgeCollapses);
  get("activeClusters", f.activeClusters);
  get("errorBoundPx", f.errorBoundPx);
  if (!bad) return bad;
  if (auto it = j.find("nodesPerLevel"); it != j.end()) {
    if (!it->is_array()) return makeError("frame field nodesPerLevel is not an array");
    for (const auto& v : *it) {
      if (!v.is_number_unsigned() || v.get<std::uint64_t>() > 0xffffffffu)
        return makeError("frame field nodesPerLevel holds a value that is not a count");
      f.nodesPerLevel.push_back(static_cast<std::uint32_t>(v.get<std::uint64_t>()));
    }
  }
  return Ok{};
}

}  // namespace

Result<std::vector<FrameRecord>> parseStatsFrames(const std::string& text) {
  const auto j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return makeError("not a JSON object");
  auto it = j.find("frames");
  if (it == j.end() || !it->is_array()) return makeError("no \"frames\" array");
  std::vector<FrameRecord> frames;
  frames.reserve(it->size());
  for (std::size_t k = 0; k < it->size(); ++k) {
    FrameRecord f;
    if (auto s = readFrameObject((*it)[k], f); !s)
      return makeError("frame " + std::to_string(k) + ": " + s.message());
    frames.push_back(std::move(f));
  }
  return frames;
}

Status writeStatsJson(const std::string& path, std::span<const FrameRecord> frames,
                      const FrameSummary& summary, const std::string& extra) {
  return writeText(path, statsJson(frames, summary, extra) + "\n");
}

Status writeStatsCsv(const std::string& path, std::span<const FrameRecord> frames) {
  return writeText(path, statsCsv(frames));
}

}  // namespace hlod
