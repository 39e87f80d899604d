// Summaries and answers of the accuracy study. See hlod/study/Study.h.
#include "hlod/study/Study.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <map>

#include "hlod/metrics/ImageMetrics.h"
#include "hlod/runtime/SseSelector.h"

namespace hlod::study {

std::string StudyConfig::label() const {
  char buf[96];
  if (selector == "sse")
    std::snprintf(buf, sizeof buf, "sse %g px", ssePx);
  else
    std::snprintf(buf, sizeof buf, "%s %g ms", selector.c_str(), budgetMs);
  return std::string(buf) + (mode == FrameMode::Realtime ? " realtime" : "");
}

namespace {

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double rank = std::ceil(q * static_cast<double>(v.size()));
  return v[static_cast<std::size_t>(std::clamp(rank, 1.0, double(v.size()))) - 1];
}

}  // namespace

RunSummary summarize(std::span<const FrameResult> frames) {
  RunSummary s;
  s.frames = frames.size();
  if (frames.empty()) return s;
  std::vector<double> ms, psnr;
  double sumMs = 0, sumTri = 0, sumPsnr = 0, sumSsim = 0, sumFlip = 0, sumSse = 0, toggles = 0;
  s.worstPsnr = kMaxPsnr;
  for (const FrameResult& f : frames) {
    ms.push_back(f.frameMs);
    psnr.push_back(f.psnr);
    sumMs += f.frameMs;
    sumTri += static_cast<double>(f.triangles);
    sumPsnr += f.psnr;
    sumSsim += f.ssim;
    sumFlip += f.flip;
    sumSse += f.sseMaxPx;
    toggles += f.toggles;
    s.bytesLoaded += f.bytesLoaded;
    s.maxMs = std::max(s.maxMs, f.frameMs);
    s.maxCoverage = std::max(s.maxCoverage, f.coverage);
    s.framesOverCoverage += f.coverage > kCoverageLimit;
    if (f.psnr < s.worstPsnr || (f.psnr == s.worstPsnr && s.worstFrame == 0)) {
      s.worstPsnr = f.psnr;
      s.worstFrame = f.frame;
    }
  }
  const double n = static_cast<double>(frames.size());
  s.meanMs = sumMs / n;
  s.p95Ms = percentile(ms, 0.95);
  s.meanTriangles = sumTri / n;
  s.medianPsnr = percentile(psnr, 0.5);
  s.meanPsnr = sumPsnr / n;
  s.meanSsim = sumSsim / n;
  s.meanFlip = sumFlip / n;
  s.meanSseMaxPx = sumSse / n;
  s.togglesPerFrame = toggles / n;
  return s;
}

void markParetoFront(std::vector<Run>& runs) {
  std::vector<std::pair<double, double>> points;
  for (const Run& r : runs) points.emplace_back(r.summary.meanMs, -r.summary.medianPsnr);
  for (Run& r : runs) r.onParetoFront = false;
  for (std::size_t i : metrics::paretoFront(points)) runs[i].onParetoFront = true;
}

FrontError frontScreenError(const Skeleton& skeleton, const View& view,
                            std::span<const std::uint32_t> front) {
  FrontError e;
  if (front.empty()) return e;
  double sum = 0.0;
  for (std::uint32_t n : front) {
    assert(n < skeleton.nodes.size());
    const double px = SseSelector::screenSpaceError(skeleton.nodes[n], view, 1.0);
    e.maxPx = std::max(e.maxPx, px);
    sum += px;
  }
  e.meanPx = sum / static_cast<double>(front.size());
  return e;
}

namespace {

// The runs of one selector in one mode, ordered by mean frame time.
std::vector<const Run*> curveOf(const std::vector<Run>& runs, const std::string& selector,
                                FrameMode mode) {
  std::vector<const Run*> out;
  for (const Run& r : runs)
    if (r.config.selector == selector && r.config.mode == mode) out.push_back(&r);
  std::sort(out.begin(), out.end(),
            [](const Run* a, const Run* b) { return a->summary.meanMs < b->summary.meanMs; });
  return out;
}

}  // namespace

Answers answer(const std::vector<Run>& runs) {
  Answers a;
  for (FrameMode mode : {FrameMode::Settled, FrameMode::Realtime}) {
    const auto sse = curveOf(runs, "sse", mode);
    for (const Run* l : curveOf(runs, "lakhia", mode)) {
      Answers::AtEqualTime e;
      e.budgetMs = l->config.budgetMs;
      e.lakhiaMs = l->summary.meanMs;
      e.lakhiaPsnr = l->summary.medianPsnr;
      e.ssePsnr = std::numeric_limits<double>::quiet_NaN();
      // Linear between the two SSE thresholds whose mean times bracket Lakhia's.
      for (std::size_t i = 1; i < sse.size(); ++i) {
        const RunSummary &p = sse[i - 1]->summary, &q = sse[i]->summary;
        if (p.meanMs <= e.lakhiaMs && e.lakhiaMs <= q.meanMs && q.meanMs > p.meanMs) {
          const double t = (e.lakhiaMs - p.meanMs) / (q.meanMs - p.meanMs);
          e.ssePsnr = p.medianPsnr + t * (q.medianPsnr - p.medianPsnr);
          break;
        }
      }
      e.gainDb = e.lakhiaPsnr - e.ssePsnr;
      for (const Run* s : sse)
        if (s->summary.meanMs <= e.lakhiaMs && s->summary.medianPsnr > e.lakhiaPsnr)
          e.lakhiaDominatedBySse = true;
      if (mode == FrameMode::Settled || !sse.empty()) a.lakhiaVsSse.push_back(e);
    }
    for (const char* sel : {"lakhia", "fs", "sse"}) {
      const auto curve = curveOf(runs, sel, mode);
      for (std::size_t i = 1; i < curve.size(); ++i) {
        Answers::Slope s;
        s.selector = std::string(sel) + (mode == FrameMode::Realtime ? " realtime" : "");
        const StudyConfig &c0 = curve[i - 1]->config, &c1 = curve[i]->config;
        s.fromBudget = sel == std::string("sse") ? c0.ssePx : c0.budgetMs;
        s.toBudget = sel == std::string("sse") ? c1.ssePx : c1.budgetMs;
        s.fromMs = curve[i - 1]->summary.meanMs;
        s.toMs = curve[i]->summary.meanMs;
        const double dMs = s.toMs - s.fromMs;
        s.dbPerMs = dMs > 1e-9
                        ? (curve[i]->summary.medianPsnr - curve[i - 1]->summary.medianPsnr) / dMs
                        : std::numeric_limits<double>::quiet_NaN();
        a.dbPerMs.push_back(s);
      }
    }
  }
  const Run* best = nullptr;
  for (const Run& r : runs)
    if (r.config.selector == "lakhia" && r.config.mode == FrameMode::Settled &&
        (!best || std::abs(r.config.budgetMs - 33.0) < std::abs(best->config.budgetMs - 33.0)))
      best = &r;
  if (best) {
    a.lakhia33Budget = best->config.budgetMs;
    a.lakhia33MedianPsnr = best->summary.medianPsnr;
    a.lakhia33WorstPsnr = best->summary.worstPsnr;
    a.lakhia33WorstFrame = best->summary.worstFrame;
    a.lakhia33MaxCoverage = best->summary.maxCoverage;
    a.lakhia33FramesOverCoverage = best->summary.framesOverCoverage;
  }
  return a;
}

std::vector<std::string> Answers::lines() const {
  std::vector<std::string> out;
  char buf[320];
  for (const auto& e : lakhiaVsSse) {
    if (std::isnan(e.ssePsnr))
      std::snprintf(buf, sizeof buf,
                    "Lakhia at %g ms (mean %.1f ms, median %.2f dB): SSE's thresholds do not reach "
                    "that frame time%s",
                    e.budgetMs, e.lakhiaMs, e.lakhiaPsnr,
                    e.lakhiaDominatedBySse ? "; an SSE threshold is faster and better" : "");
    else
      std::snprintf(buf, sizeof buf,
                    "Lakhia at %g ms (mean %.1f ms): median %.2f dB, SSE at the same mean time "
                    "%.2f dB: %+.2f dB%s",
                    e.budgetMs, e.lakhiaMs, e.lakhiaPsnr, e.ssePsnr, e.gainDb,
                    e.lakhiaDominatedBySse ? " (below SSE's Pareto front)"
                                           : " (on or above SSE's Pareto front)");
    out.push_back(buf);
  }
  for (const auto& s : dbPerMs) {
    std::snprintf(buf, sizeof buf, "%s %g -> %g: %.1f -> %.1f ms, %.3f dB per extra ms",
                  s.selector.c_str(), s.fromBudget, s.toBudget, s.fromMs, s.toMs, s.dbPerMs);
    out.push_back(buf);
  }
  if (lakhia33Budget > 0.0) {
    std::snprintf(buf, sizeof buf,
                  "Lakhia at %g ms: median PSNR %.2f dB, worst %.2f dB (frame %llu); largest "
                  "coverage difference %.2f%% of pixels, %zu frame(s) over %.1f%%",
                  lakhia33Budget, lakhia33MedianPsnr, lakhia33WorstPsnr,
                  static_cast<unsigned long long>(lakhia33WorstFrame), 100.0 * lakhia33MaxCoverage,
                  lakhia33FramesOverCoverage, 100.0 * kCoverageLimit);
    out.push_back(buf);
  }
  return out;
}

}  // namespace hlod::study
