// A run's per-frame timing as Chrome Trace Event JSON. See service/ChromeTrace.h.
#include "service/ChromeTrace.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <fstream>
#include <limits>
#include <utility>

namespace service {

namespace {

using Ns = std::int64_t;  // nanoseconds from the trace's origin, whole microseconds (toNs)

// A slice before it is placed: where its step began and how long it took.
struct Step {
  std::string name;
  Ns start = 0;
  Ns dur = 0;
};

// The passes in the order the renderer runs them (Renderer.cpp, VdrNodeRenderer.cpp: refine
// prepares the clusters before the inner renderer draws; the occlusion queries' boxes follow
// the geometry they test against).
const std::pair<const char*, double hlod::FrameRecord::*> kPasses[] = {
    {"refine", &hlod::FrameRecord::refineMs},
    {"shadow", &hlod::FrameRecord::shadowMs},
    {"geometry", &hlod::FrameRecord::geometryMs},
    {"occlusion", &hlod::FrameRecord::occlusionMs},
    {"sky", &hlod::FrameRecord::skyMs},
    {"ssao", &hlod::FrameRecord::ssaoMs},
    {"ssao-blur", &hlod::FrameRecord::ssaoBlurMs},
    {"composite", &hlod::FrameRecord::compositeMs},
    {"outline", &hlod::FrameRecord::outlineMs}};

const char* const kPassPlacement =
    "select, upload, draw, readback and encode start where they were measured (steady clock); "
    "the passes are GPU durations laid end to end from the draw's start, inside it";

// Whole microseconds (held as nanoseconds), so that nesting holds exactly, here and in a
// viewer: a viewer adds ts and dur in floating point, which is exact for whole numbers only (at
// a nanosecond grid 67672.799 + 23969.139 came out past its last child's end, and speedscope
// took the child for an overlap). A NaN or an infinity is 0.
Ns toNs(double us) {
  if (!std::isfinite(us)) return 0;
  const double ns = std::round(us) * 1e3;
  constexpr double kMax = 4e18;
  return static_cast<Ns>(std::clamp(ns, -kMax, kMax));
}
Ns msToNs(double ms) {
  return ms > 0.0 ? toNs(ms * 1e3) : 0;
}
// A counter's or an arg's value: NaN has no JSON spelling (nlohmann writes null).
double finite(double v) {
  return std::isfinite(v) ? v : 0.0;
}
double toUs(Ns ns) {
  assert(ns % 1000 == 0);
  return static_cast<double>(ns / 1000);
}

bool hasTimeline(const hlod::FrameTimeline& t) {
  return t.startUs != 0.0 || t.selectStartUs != 0.0 || t.drawEndUs != 0.0;
}

nlohmann::json slice(const std::string& name, Ns start, Ns dur, int pid,
                     nlohmann::json args = nlohmann::json::object()) {
  return {{"name", name},     {"cat", "frame"}, {"ph", "X"}, {"ts", toUs(start)},
          {"dur", toUs(dur)}, {"pid", pid},     {"tid", 1},  {"args", std::move(args)}};
}

nlohmann::json counter(const std::string& name, Ns at, int pid, nlohmann::json args) {
  return {{"name", name}, {"cat", "frame"},         {"ph", "C"}, {"ts", toUs(at)}, {"pid", pid},
          {"tid", 1},     {"args", std::move(args)}};
}

nlohmann::json metadata(const std::string& what, int pid, const std::string& name) {
  return {{"name", what}, {"ph", "M"}, {"ts", 0},
          {"pid", pid},   {"tid", 1},  {"args", {{"name", name}}}};
}

// Puts `steps` (in the order they ran) inside [begin, end], each after the one before: a step
// that would start before its predecessor ended or end after its parent is cut (counted).
std::vector<Step> nest(std::vector<Step> steps, Ns begin, Ns end, std::uint64_t& clipped) {
  std::stable_sort(steps.begin(), steps.end(),
                   [](const Step& a, const Step& b) { return a.start < b.start; });
  Ns cursor = begin;
  for (Step& s : steps) {
    const Ns start = std::clamp(s.start, cursor, end);
    const Ns stop = std::clamp(s.start + s.dur, start, end);
    if (start != s.start || stop - start != s.dur) ++clipped;
    s.start = start;
    s.dur = stop - start;
    cursor = stop;
  }
  return steps;
}

}  // namespace

nlohmann::json chromeTrace(std::span<const TraceRun> runs, const nlohmann::json& otherData) {
  // The origin: the earliest frame start that was recorded, so that the trace begins near 0.
  double originUs = std::numeric_limits<double>::infinity();
  for (const TraceRun& run : runs)
    for (const hlod::FrameRecord& f : run.frames)
      if (hasTimeline(f.timeline)) originUs = std::min(originUs, f.timeline.startUs);
  if (!std::isfinite(originUs)) originUs = 0.0;
  auto at = [&](double us) { return toNs(us - originUs); };

  nlohmann::json events = nlohmann::json::array();
  nlohmann::json runList = nlohmann::json::array();
  std::uint64_t clipped = 0, untimed = 0;
  Ns lastEnd = 0;  // where a frame without a timeline goes
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const TraceRun& run = runs[r];
    const int pid = static_cast<int>(r) + 1;
    events.push_back(metadata("process_name", pid, run.name));
    events.push_back(metadata("thread_name", pid, "frames"));
    runList.push_back({{"pid", pid}, {"name", run.name}, {"settings", run.settings}});
    for (const hlod::FrameRecord& f : run.frames) {
      const hlod::FrameTimeline& t = f.timeline;
      const bool timed = hasTimeline(t);
      if (!timed) ++untimed;
      // Untimed: the starts are set below, each step where the one before ended.
      auto when = [&](double us) { return timed ? at(us) : Ns{0}; };
      const Ns start = timed ? at(t.startUs) : lastEnd;
      std::vector<Step> steps;
      steps.push_back({"select", when(t.selectStartUs), msToNs(f.selectorMs)});
      if (f.uploadMs > 0.0 || f.uploads > 0)
        steps.push_back({"upload", when(t.uploadStartUs), msToNs(f.uploadMs)});
      Ns drawDur = timed ? std::max<Ns>(0, at(t.drawEndUs) - at(t.drawStartUs)) : msToNs(f.drawMs);
      steps.push_back({"draw", when(t.drawStartUs), drawDur});
      if (t.readbackUs > 0.0)
        steps.push_back({"readback", when(t.readbackStartUs), toNs(t.readbackUs)});
      if (t.encodeUs > 0.0) steps.push_back({"encode", when(t.encodeStartUs), toNs(t.encodeUs)});
      // The frame: renderFrame's wall time, and on to the end of its readback and encode.
      Ns end = start + msToNs(f.wallMs);
      if (!timed) {
        // Laid out from the frame's start, in the order the driver runs them.
        Ns cursor = start;
        for (Step& s : steps) {
          s.start = cursor;
          cursor += s.dur;
        }
        end = std::max(end, cursor);
      } else {
        for (const Step& s : steps)
          if (s.name == "readback" || s.name == "encode") end = std::max(end, s.start + s.dur);
      }
      steps = nest(std::move(steps), start, end, clipped);
      lastEnd = std::max(lastEnd, end);

      events.push_back(slice("frame " + std::to_string(f.index), start, end - start, pid,
                             {{"index", f.index},
                              {"time", finite(f.time)},
                              {"targetMs", finite(f.targetMs)},
                              {"gpuMs", finite(f.gpuMs)},
                              {"wallMs", finite(f.wallMs)},
                              {"triangles", f.triangles}}));
      // A slice of no time is left out: at its parent's end the viewers would take it for a
      // sibling of the parent.
      for (const Step& s : steps) {
        if (s.dur <= 0) continue;
        events.push_back(slice(s.name, s.start, s.dur, pid));
        if (s.name != "draw") continue;
        // The passes: GPU durations, end to end from the draw's start.
        std::vector<Step> passes;
        std::vector<double> measured;
        Ns cursor = s.start;
        for (const auto& [name, field] : kPasses) {
          const Ns dur = msToNs(f.*field);
          if (dur <= 0) continue;
          passes.push_back({name, cursor, dur});
          measured.push_back(f.*field);
          cursor += dur;
        }
        passes = nest(std::move(passes), s.start, s.start + s.dur, clipped);
        for (std::size_t i = 0; i < passes.size(); ++i)
          if (passes[i].dur > 0)
            events.push_back(slice(passes[i].name, passes[i].start, passes[i].dur, pid,
                                   {{"gpuMs", finite(measured[i])}}));
      }
      events.push_back(counter("resident bytes", end, pid,
                               {{"bytes", f.residentBytes}, {"capBytes", f.capBytes}}));
      events.push_back(counter("gpu bytes", end, pid, {{"bytes", f.gpuBytes}}));
      events.push_back(counter("v_time", end, pid, {{"msPerCost", finite(f.vTime)}}));
      events.push_back(counter("frame time", end, pid,
                               {{"gpuMs", finite(f.gpuMs)}, {"targetMs", finite(f.targetMs)}}));
    }
  }
  nlohmann::json other = otherData.is_object() ? otherData : nlohmann::json::object();
  other["runs"] = std::move(runList);
  other["clippedSlices"] = clipped;
  other["framesWithoutTimeline"] = untimed;
  other["passPlacement"] = kPassPlacement;
  return {{"traceEvents", std::move(events)},
          {"displayTimeUnit", "ms"},
          {"otherData", std::move(other)}};
}

hlod::Status writeChromeTrace(const std::string& path, std::span<const TraceRun> runs,
                              const nlohmann::json& otherData) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return hlod::makeError("cannot write " + path);
  out << chromeTrace(runs, otherData).dump() << "\n";
  out.close();
  if (!out) return hlod::makeError("cannot write " + path);
  return hlod::Ok{};
}

ChromeTraceSink::ChromeTraceSink(std::string path, std::string name, nlohmann::json settings)
    : path_(std::move(path)), name_(std::move(name)), settings_(std::move(settings)) {}

hlod::Status ChromeTraceSink::onFrame(const hlod::FrameRecord& record, const hlod::Image*) {
  frames_.push_back(record);
  return hlod::Ok{};
}

hlod::Status ChromeTraceSink::finish() {
  const TraceRun run{name_, frames_, settings_};
  return writeChromeTrace(path_, std::span<const TraceRun>(&run, 1));
}

}  // namespace service
