#pragma once
// Checks a trace against the Trace Event Format (JSON Object Format) and what Perfetto UI and
// chrome://tracing need of it: every event has name, ph, ts, pid and tid; complete events ("X")
// a dur >= 0; counters ("C") numeric args; metadata ("M") a name arg. On each thread the X
// slices nest strictly (a slice that starts inside another ends inside it: siblings never
// overlap), the top-level slices are the frames, "frame N" with N increasing, and every
// other slice is one of the frame's steps or passes. Returns the problems found (empty: none).
#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace tracecheck {

struct Slice {
  std::string name;
  double ts = 0.0, dur = 0.0;
  double end() const { return ts + dur; }
};

inline std::vector<std::string> traceProblems(const nlohmann::json& trace) {
  std::vector<std::string> problems;
  auto fail = [&](const std::string& what) {
    if (problems.size() < 20) problems.push_back(what);
  };
  if (!trace.is_object() || !trace.contains("traceEvents") || !trace["traceEvents"].is_array())
    return {"no traceEvents array"};
  if (trace.value("displayTimeUnit", "") != "ms") fail("displayTimeUnit is not \"ms\"");
  if (!trace.contains("otherData") || !trace["otherData"].is_object()) fail("no otherData");
  static const std::set<std::string> kChildren = {
      "select",   "upload",    "draw", "readback", "encode",    "refine",    "shadow",
      "geometry", "occlusion", "sky",  "ssao",     "ssao-blur", "composite", "outline"};
  std::map<std::pair<long long, long long>, std::vector<Slice>> threads;
  for (const auto& e : trace["traceEvents"]) {
    const std::string what = e.dump();
    if (!e.is_object() || !e.contains("name") || !e["name"].is_string() || !e.contains("ph") ||
        !e["ph"].is_string() || !e.contains("ts") || !e["ts"].is_number() || !e.contains("pid") ||
        !e["pid"].is_number_integer() || !e.contains("tid") || !e["tid"].is_number_integer()) {
      fail("an event without name, ph, ts, pid or tid: " + what);
      continue;
    }
    const std::string ph = e["ph"];
    if (ph == "X") {
      if (!e.contains("dur") || !e["dur"].is_number() || e["dur"].get<double>() < 0.0)
        fail("a complete event without a dur >= 0: " + what);
      else
        threads[{e["pid"], e["tid"]}].push_back(
            {e["name"], e["ts"].get<double>(), e["dur"].get<double>()});
    } else if (ph == "C") {
      if (!e.contains("args") || !e["args"].is_object() || e["args"].empty())
        fail("a counter without args: " + what);
      else
        for (const auto& [k, v] : e["args"].items())
          if (!v.is_number()) fail("a counter's arg " + k + " is not a number: " + what);
    } else if (ph == "M") {
      if (!e.contains("args") || !e["args"].contains("name") || !e["args"]["name"].is_string())
        fail("a metadata event without a name arg: " + what);
    } else {
      fail("an event of a phase this writer does not write: " + what);
    }
  }
  // None: a viewer compares ts + dur in floating point as this does (speedscope reported
  // children that ended 1e-11 us after their frame as overlaps).
  constexpr double kEps = 0.0;
  for (auto& [thread, slices] : threads) {
    // Parents first: by start, the longer first where two start together.
    std::stable_sort(slices.begin(), slices.end(), [](const Slice& a, const Slice& b) {
      return a.ts != b.ts ? a.ts < b.ts : a.dur > b.dur;
    });
    std::vector<const Slice*> open;
    long long lastFrame = -1;
    for (const Slice& s : slices) {
      while (!open.empty() && open.back()->end() <= s.ts + kEps) open.pop_back();
      if (!open.empty() && s.end() > open.back()->end() + kEps)
        fail(s.name + " at " + std::to_string(s.ts) + " overlaps " + open.back()->name +
             " without nesting in it");
      if (open.empty()) {
        if (s.name.rfind("frame ", 0) != 0) {
          fail("a top-level slice that is not a frame: " + s.name);
        } else {
          const long long n = std::stoll(s.name.substr(6));
          if (n <= lastFrame) fail("frames out of order: " + s.name);
          lastFrame = n;
        }
      } else if (!kChildren.count(s.name)) {
        fail("an unknown slice in a frame: " + s.name);
      }
      open.push_back(&s);
    }
  }
  return problems;
}

// The X slices named `name`, in the order they appear.
inline std::vector<Slice> slicesNamed(const nlohmann::json& trace, const std::string& name) {
  std::vector<Slice> out;
  for (const auto& e : trace["traceEvents"])
    if (e.value("ph", "") == "X" && e.value("name", "") == name)
      out.push_back({name, e["ts"].get<double>(), e["dur"].get<double>()});
  return out;
}

// The frames' slices ("frame N"), in the order they appear.
inline std::vector<Slice> frameSlices(const nlohmann::json& trace) {
  std::vector<Slice> out;
  for (const auto& e : trace["traceEvents"])
    if (e.value("ph", "") == "X" && e.value("name", "").rfind("frame ", 0) == 0)
      out.push_back({e["name"], e["ts"].get<double>(), e["dur"].get<double>()});
  return out;
}

}  // namespace tracecheck
