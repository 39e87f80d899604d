// The Chrome trace writer (service/ChromeTrace.h) against the Trace Event Format, on frame
// records built by hand: the JSON shape, slices that nest and do not overlap, numeric counters,
// frames in order, and where the steps and passes are placed.
#include "service/ChromeTrace.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "ChromeTraceCheck.h"

namespace {

using hlod::FrameRecord;
using nlohmann::json;

// A realtime frame at `startUs` (any epoch): upload 1 ms, select 0.5 ms, draw 6 ms with shadow
// 1 ms and geometry 3 ms, readback 0.4 ms, encode 2 ms; wall 8 ms.
FrameRecord frameAt(std::uint64_t index, double startUs) {
  FrameRecord f;
  f.index = index;
  f.time = index / 30.0;
  f.targetMs = 33.0;
  f.gpuMs = 7.0;
  f.wallMs = 8.0;
  f.uploadMs = 1.0;
  f.uploads = 2;
  f.selectorMs = 0.5;
  f.shadowMs = 1.0;
  f.geometryMs = 3.0;
  f.vTime = 0.002;
  f.residentBytes = 1000 + index;
  f.gpuBytes = 500 + index;
  hlod::FrameTimeline& t = f.timeline;
  t.startUs = startUs;
  t.uploadStartUs = startUs + 100;
  t.selectStartUs = startUs + 1200;
  t.drawStartUs = startUs + 1800;
  t.drawEndUs = startUs + 7800;
  t.readbackStartUs = startUs + 8000;
  t.readbackUs = 400;
  t.encodeStartUs = startUs + 8500;
  t.encodeUs = 2000;
  return f;
}

json traceOf(const std::vector<FrameRecord>& frames) {
  const service::TraceRun run{"test run", frames, {{"budgetMs", 33}}};
  return service::chromeTrace(std::span<const service::TraceRun>(&run, 1), {{"note", "unit"}});
}

std::string problems(const json& trace) {
  std::string all;
  for (const auto& p : tracecheck::traceProblems(trace)) all += p + "\n";
  return all;
}

const json* event(const json& trace, const std::string& name, std::size_t nth = 0) {
  for (const auto& e : trace["traceEvents"])
    if (e["name"] == name && nth-- == 0) return &e;
  return nullptr;
}

TEST(ChromeTrace, AFrameSequenceIsAValidTraceWithNestedSlicesAndNumericCounters) {
  std::vector<FrameRecord> frames;
  for (int i = 0; i < 3; ++i) frames.push_back(frameAt(i, 5e9 + i * 20000.0));
  const json trace = traceOf(frames);
  // Written and read back as text, as a viewer gets it.
  const json text = json::parse(trace.dump());
  EXPECT_EQ(problems(text), "");
  EXPECT_EQ(text["displayTimeUnit"], "ms");
  EXPECT_EQ(text["otherData"]["note"], "unit");
  EXPECT_EQ(text["otherData"]["runs"][0]["name"], "test run");
  EXPECT_EQ(text["otherData"]["runs"][0]["settings"]["budgetMs"], 33);
  EXPECT_EQ(text["otherData"]["clippedSlices"], 0);
  const auto frameSlices = tracecheck::frameSlices(text);
  ASSERT_EQ(frameSlices.size(), 3u);
  EXPECT_EQ(frameSlices[0].name, "frame 0");
  EXPECT_EQ(frameSlices[2].name, "frame 2");
  // Every step once per frame; the passes that ran, not those that did not.
  for (const char* name : {"select", "upload", "draw", "shadow", "geometry", "readback", "encode"})
    EXPECT_EQ(tracecheck::slicesNamed(text, name).size(), 3u) << name;
  for (const char* name : {"sky", "ssao", "outline", "refine", "occlusion"})
    EXPECT_TRUE(tracecheck::slicesNamed(text, name).empty()) << name;
  for (const char* name : {"resident bytes", "gpu bytes", "v_time", "frame time"}) {
    const json* c = event(text, name, 2);
    ASSERT_NE(c, nullptr) << name;
    EXPECT_EQ((*c)["ph"], "C");
  }
  EXPECT_EQ((*event(text, "resident bytes", 2))["args"]["bytes"], 1002);
  EXPECT_EQ((*event(text, "gpu bytes", 1))["args"]["bytes"], 501);
  EXPECT_DOUBLE_EQ((*event(text, "v_time"))["args"]["msPerCost"].get<double>(), 0.002);
  EXPECT_EQ((*event(text, "process_name"))["args"]["name"], "test run");
  EXPECT_EQ((*event(text, "thread_name"))["ph"], "M");
}

// Measured times fall anywhere: the trace puts them on whole microseconds, where a viewer's
// ts + dur is exact, so that a step that ends with its frame ends exactly there and not 1e-11 us
// after it (which speedscope took for an overlap).
TEST(ChromeTrace, TimesOffTheMicrosecondGridNestExactlyAsAViewerAddsThem) {
  std::vector<FrameRecord> frames;
  double at = 5e9 + 0.799;
  for (int i = 0; i < 200; ++i) {
    FrameRecord f = frameAt(i, at);
    f.wallMs = 8.000339 + 0.013 * i;
    f.uploadMs = 1.000417;
    f.timeline.readbackUs = 400.113;
    f.timeline.encodeStartUs += 0.419;
    // The encode ends with the frame: 8,000.339 + 13 i us after its start.
    f.timeline.encodeUs = f.wallMs * 1e3 - (f.timeline.encodeStartUs - f.timeline.startUs);
    frames.push_back(f);
    at += 23969.139 + 0.001 * i;
  }
  const json text = json::parse(traceOf(frames).dump());
  EXPECT_EQ(problems(text), "");
  for (const auto& e : text["traceEvents"]) {
    if (e["ph"] == "M") continue;
    EXPECT_EQ(std::floor(e["ts"].get<double>()), e["ts"].get<double>()) << e.dump();
    if (e.contains("dur")) {
      EXPECT_EQ(std::floor(e["dur"].get<double>()), e["dur"].get<double>());
    }
  }
}

TEST(ChromeTrace, StepsStartWhereTheyWereMeasuredAndPassesFollowEachOtherInTheDraw) {
  const json trace = traceOf({frameAt(0, 1e6), frameAt(1, 1e6 + 20000)});
  ASSERT_EQ(problems(trace), "");
  // ts 0 is the first frame's start; microseconds.
  EXPECT_DOUBLE_EQ(tracecheck::frameSlices(trace)[0].ts, 0.0);
  EXPECT_DOUBLE_EQ(tracecheck::frameSlices(trace)[1].ts, 20000.0);
  EXPECT_DOUBLE_EQ(tracecheck::slicesNamed(trace, "upload")[0].ts, 100.0);
  EXPECT_DOUBLE_EQ(tracecheck::slicesNamed(trace, "upload")[0].dur, 1000.0);
  EXPECT_DOUBLE_EQ(tracecheck::slicesNamed(trace, "select")[1].ts, 21200.0);
  EXPECT_DOUBLE_EQ(tracecheck::slicesNamed(trace, "select")[1].dur, 500.0);
  EXPECT_DOUBLE_EQ(tracecheck::slicesNamed(trace, "draw")[0].ts, 1800.0);
  EXPECT_DOUBLE_EQ(tracecheck::slicesNamed(trace, "draw")[0].dur, 6000.0);
  EXPECT_DOUBLE_EQ(tracecheck::slicesNamed(trace, "shadow")[0].ts, 1800.0);
  EXPECT_DOUBLE_EQ(tracecheck::slicesNamed(trace, "geometry")[0].ts, 2800.0);
  EXPECT_DOUBLE_EQ(tracecheck::slicesNamed(trace, "geometry")[0].dur, 3000.0);
  // The frame runs on to the end of its encode, past renderFrame's wall time.
  EXPECT_DOUBLE_EQ(tracecheck::frameSlices(trace)[0].dur, 10500.0);
}

TEST(ChromeTrace, MeasurementsThatWouldOverflowAreCutToNestAndCounted) {
  FrameRecord f = frameAt(0, 1e6);
  f.timeline.uploadStartUs = f.timeline.startUs + 300;  // ends 100 us into select
  f.geometryMs = 20.0;                                  // longer than the draw
  f.compositeMs = 1.0;                                  // after it: nothing left
  f.timeline.encodeUs = std::numeric_limits<double>::quiet_NaN();
  f.vTime = std::numeric_limits<double>::infinity();
  const json trace = json::parse(traceOf({f}).dump());
  EXPECT_EQ(problems(trace), "");
  EXPECT_EQ(trace["otherData"]["clippedSlices"], 3);  // select, geometry, composite
  EXPECT_DOUBLE_EQ(tracecheck::slicesNamed(trace, "select")[0].ts, 1300.0);
  const auto draw = tracecheck::slicesNamed(trace, "draw")[0];
  const auto geometry = tracecheck::slicesNamed(trace, "geometry")[0];
  EXPECT_DOUBLE_EQ(geometry.end(), draw.end());
  EXPECT_TRUE(tracecheck::slicesNamed(trace, "composite").empty());
  EXPECT_TRUE(tracecheck::slicesNamed(trace, "encode").empty());
  EXPECT_EQ((*event(trace, "v_time"))["args"]["msPerCost"], 0.0);
}

TEST(ChromeTrace, FramesWithoutATimelineAreLaidOutEndToEnd) {
  FrameRecord a = frameAt(0, 0.0), b = frameAt(1, 0.0);
  a.timeline = b.timeline = {};
  a.drawMs = b.drawMs = 5.0;
  const json trace = traceOf({a, b});
  EXPECT_EQ(problems(trace), "");
  EXPECT_EQ(trace["otherData"]["framesWithoutTimeline"], 2);
  const auto frames = tracecheck::frameSlices(trace);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_DOUBLE_EQ(frames[1].ts, frames[0].end());
  // select, upload, draw in the driver's order from the frame's start.
  EXPECT_DOUBLE_EQ(tracecheck::slicesNamed(trace, "upload")[0].ts, 500.0);
  EXPECT_DOUBLE_EQ(tracecheck::slicesNamed(trace, "draw")[0].ts, 1500.0);
}

TEST(ChromeTrace, EachRunIsAProcessOfItsOwn) {
  const std::vector<FrameRecord> first = {frameAt(0, 1e6), frameAt(1, 1.02e6)};
  const std::vector<FrameRecord> second = {frameAt(0, 2e6)};
  const std::vector<service::TraceRun> runs = {{"lakhia 33 ms", first, {}},
                                               {"sse 4 px", second, {}}};
  const json trace = service::chromeTrace(runs);
  EXPECT_EQ(problems(trace), "");
  std::vector<std::string> names;
  for (const auto& e : trace["traceEvents"])
    if (e["name"] == "process_name") names.push_back(e["args"]["name"]);
  EXPECT_EQ(names, (std::vector<std::string>{"lakhia 33 ms", "sse 4 px"}));
  EXPECT_EQ((*event(trace, "frame 0", 1))["pid"], 2);
  EXPECT_DOUBLE_EQ((*event(trace, "frame 0", 1))["ts"].get<double>(), 1e6);
}

TEST(ChromeTrace, TheCheckFindsOverlappingSiblingsAndFramesOutOfOrder) {
  // The checker itself: a trace that breaks the rules is caught.
  json bad = traceOf({frameAt(0, 1e6), frameAt(1, 1.02e6)});
  for (auto& e : bad["traceEvents"])
    if (e["name"] == "select") e["dur"] = 5000.0;  // over the draw, past its end
  EXPECT_NE(problems(bad), "");
  json swapped = traceOf({frameAt(1, 1e6), frameAt(0, 1.02e6)});
  EXPECT_NE(problems(swapped).find("out of order"), std::string::npos);
  json noPid = traceOf({frameAt(0, 1e6)});
  noPid["traceEvents"][0].erase("pid");
  EXPECT_NE(problems(noPid), "");
}

TEST(ChromeTrace, WritesTheFileAndSaysWhenItCannot) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("hlodr_trace_" + std::to_string(::getpid()) + ".json");
  const std::vector<FrameRecord> frames = {frameAt(0, 1e6)};
  const service::TraceRun run{"r", frames, {}};
  ASSERT_TRUE(service::writeChromeTrace(path.string(), std::span(&run, 1)).ok());
  std::ifstream in(path);
  const json read = json::parse(in, nullptr, false);
  EXPECT_EQ(problems(read), "");
  std::filesystem::remove(path);
  EXPECT_FALSE(service::writeChromeTrace("/nonexistent-dir/t.json", std::span(&run, 1)).ok());
}

}  // namespace
