// Segments of a path run (hlod/runtime/Segments.h): the frame ranges, the "i/N" argument, the
// checks before a join, and the stats reader the join uses.
#include <gtest/gtest.h>

#include "hlod/runtime/FrameStats.h"
#include "hlod/runtime/Segments.h"

namespace {

hlod::SegmentPart part(std::uint32_t index, std::uint32_t count, std::uint64_t total) {
  hlod::SegmentPart p;
  p.name = "part" + std::to_string(index);
  p.spec = {index, count};
  p.range = hlod::segmentRange(total, index, count);
  p.runFrames = total;
  p.width = 320;
  p.height = 180;
  p.fps = 30.0;
  for (std::uint64_t i = p.range.first; i < p.range.end; ++i) {
    hlod::FrameRecord r;
    r.index = i;
    p.frames.push_back(r);
  }
  return p;
}

}  // namespace

TEST(SegmentsTest, RangesCoverEveryFrameOnceInOrder) {
  for (std::uint64_t total : {1u, 2u, 7u, 600u, 601u}) {
    for (std::uint32_t n = 1; n <= 7 && n <= total; ++n) {
      std::uint64_t next = 0;
      for (std::uint32_t i = 0; i < n; ++i) {
        const hlod::FrameRange r = hlod::segmentRange(total, i, n);
        EXPECT_EQ(r.first, next) << total << " frames, segment " << i << "/" << n;
        EXPECT_GT(r.end, r.first) << "no segment is empty when N <= F";
        next = r.end;
      }
      EXPECT_EQ(next, total);
    }
  }
  EXPECT_EQ(hlod::segmentRange(600, 1, 2).first, 300u);
  // Large counts do not overflow i*F.
  const std::uint64_t huge = std::uint64_t{1} << 62;
  EXPECT_EQ(hlod::segmentRange(huge, 1023, 1024).end, huge);
}

TEST(SegmentsTest, ParsesIOverNAndSaysWhatIsWrongWithAnythingElse) {
  auto ok = hlod::parseSegment("1/2");
  ASSERT_TRUE(ok.ok()) << ok.message();
  EXPECT_EQ(ok->index, 1u);
  EXPECT_EQ(ok->count, 2u);
  for (const char* bad : {"", "1", "/2", "1/", "2/2", "3/2", "0/0", "-1/2", "1/-2", "a/b", "1/2/3",
                          " 1/2", "0/2000", "0x1/2", "99999999999999999999/2"}) {
    auto r = hlod::parseSegment(bad);
    EXPECT_FALSE(r.ok()) << "'" << bad << "'";
    if (!r.ok()) {
      EXPECT_NE(r.message().find("--segment"), std::string::npos) << r.message();
    }
  }
}

TEST(SegmentsTest, JoinsPartsGivenInAnyOrder) {
  std::vector<hlod::SegmentPart> parts = {part(2, 3, 100), part(0, 3, 100), part(1, 3, 100)};
  auto order = hlod::segmentOrder(parts);
  ASSERT_TRUE(order.ok()) << order.message();
  EXPECT_EQ(*order, (std::vector<std::size_t>{1, 2, 0}));
}

TEST(SegmentsTest, RefusesAGapAnOverlapAndPartsOfDifferentRuns) {
  auto gap = hlod::segmentOrder({part(0, 3, 100), part(2, 3, 100)});
  ASSERT_FALSE(gap.ok());
  EXPECT_NE(gap.message().find("missing"), std::string::npos) << gap.message();
  auto tail = hlod::segmentOrder({part(0, 2, 100)});
  ASSERT_FALSE(tail.ok());
  EXPECT_NE(tail.message().find("frames 50..99 are missing"), std::string::npos) << tail.message();
  auto twice = hlod::segmentOrder({part(0, 2, 100), part(0, 2, 100), part(1, 2, 100)});
  ASSERT_FALSE(twice.ok());
  EXPECT_NE(twice.message().find("overlaps"), std::string::npos) << twice.message();
  auto split = hlod::segmentOrder({part(0, 2, 100), part(1, 3, 100)});
  EXPECT_FALSE(split.ok());
  auto size = part(1, 2, 100);
  size.width = 640;
  auto sized = hlod::segmentOrder({part(0, 2, 100), size});
  ASSERT_FALSE(sized.ok());
  EXPECT_NE(sized.message().find("sizes differ"), std::string::npos) << sized.message();
  auto rate = part(1, 2, 100);
  rate.fps = 25.0;
  EXPECT_FALSE(hlod::segmentOrder({part(0, 2, 100), rate}).ok());
  auto unfinished = part(1, 2, 100);
  unfinished.frames.pop_back();
  auto u = hlod::segmentOrder({part(0, 2, 100), unfinished});
  ASSERT_FALSE(u.ok());
  EXPECT_NE(u.message().find("unfinished"), std::string::npos) << u.message();
}

TEST(SegmentsTest, StatsFramesReadBackAsWritten) {
  // Every field set to a value of its own: a field the reader forgets comes back as 0.
  hlod::FrameRecord f;
  f.index = 41;
  double x = 1.5;
  for (double* d :
       {&f.time,     &f.targetMs,   &f.estimatedMs, &f.gpuMs,     &f.cpuMs,      &f.selectorMs,
        &f.uploadMs, &f.drawMs,     &f.queryGpuMs,  &f.shadowMs,  &f.geometryMs, &f.skyMs,
        &f.ssaoMs,   &f.ssaoBlurMs, &f.compositeMs, &f.outlineMs, &f.vTime,      &f.occlusionMs,
        &f.wallMs,   &f.refineMs,   &f.errorBoundPx})
    *d = (x += 1.25);
  std::uint32_t k = 3;
  for (std::uint32_t* u :
       {&f.upToggles, &f.downToggles, &f.coarserNotResident, &f.stalls, &f.uploads,
        &f.pendingUploads, &f.partialNodes, &f.splatNodes, &f.cellNodes, &f.occlusionQueries,
        &f.occludedNodes, &f.listIn, &f.listOut, &f.gpuEvictions, &f.vertexSplits, &f.edgeCollapses,
        &f.activeClusters})
    *u = ++k;
  std::uint64_t big = 1ull << 40;
  for (std::uint64_t* u :
       {&f.triangles, &f.residentBytes, &f.capBytes, &f.loadsStarted, &f.loadsFinished, &f.unloads,
        &f.uploadBytes, &f.loadErrors, &f.bytesRead, &f.cacheHits, &f.splats, &f.occludedTriangles,
        &f.gpuBytes})
    *u = ++big;
  f.occlusion = true;
  f.nodesPerLevel = {1, 4, 16};
  const std::vector<hlod::FrameRecord> frames = {f, hlod::FrameRecord{}};
  const std::string text = hlod::statsJson(frames, hlod::summarize(frames), "{\"fps\":30}");
  auto back = hlod::parseStatsFrames(text);
  ASSERT_TRUE(back.ok()) << back.message();
  ASSERT_EQ(back->size(), 2u);
  EXPECT_EQ(hlod::frameJson((*back)[0]), hlod::frameJson(f));
  EXPECT_EQ(hlod::frameJson((*back)[1]), hlod::frameJson(hlod::FrameRecord{}));
  EXPECT_FALSE(hlod::parseStatsFrames("{\"frames\": 3}").ok());
  EXPECT_FALSE(hlod::parseStatsFrames("{\"frames\": [{\"index\": -1}]}").ok());
  EXPECT_FALSE(hlod::parseStatsFrames("not json").ok());
}
