// The study's files. See hlod/study/StudyReport.h.
#include "hlod/study/StudyReport.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "hlod/runtime/Plots.h"

namespace hlod::study {

namespace {

const char* kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e",
                         "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};

const char* colorOf(const std::string& selector) {
  if (selector == "lakhia") return kColors[0];
  if (selector == "sse") return kColors[1];
  if (selector == "fs") return kColors[2];
  return kColors[7];
}

double finiteOr(double v, double fallback = 0.0) {
  return std::isfinite(v) ? v : fallback;
}

nlohmann::json summaryJson(const RunSummary& s) {
  return {{"frames", s.frames},
          {"meanMs", s.meanMs},
          {"p95Ms", s.p95Ms},
          {"maxMs", s.maxMs},
          {"meanTriangles", s.meanTriangles},
          {"medianPsnr", s.medianPsnr},
          {"meanPsnr", s.meanPsnr},
          {"worstPsnr", s.worstPsnr},
          {"worstFrame", s.worstFrame},
          {"meanSsim", s.meanSsim},
          {"meanFlip", s.meanFlip},
          {"maxCoverage", s.maxCoverage},
          {"framesOverCoverage", s.framesOverCoverage},
          {"meanSseMaxPx", s.meanSseMaxPx},
          {"togglesPerFrame", s.togglesPerFrame},
          {"bytesLoaded", s.bytesLoaded}};
}

nlohmann::json configJson(const StudyConfig& c) {
  nlohmann::json j = {{"selector", c.selector},
                      {"label", c.label()},
                      {"mode", c.mode == FrameMode::Settled ? "settled" : "realtime"}};
  if (c.selector == "sse")
    j["ssePx"] = c.ssePx;
  else
    j["budgetMs"] = c.budgetMs;
  return j;
}

// The runs of a selector and mode, in order of their mean frame time.
std::vector<const Run*> family(const StudyReport& r, const std::string& selector, FrameMode mode) {
  std::vector<const Run*> out;
  for (const Run& run : r.runs)
    if (run.config.selector == selector && run.config.mode == mode) out.push_back(&run);
  std::sort(out.begin(), out.end(),
            [](const Run* a, const Run* b) { return a->summary.meanMs < b->summary.meanMs; });
  return out;
}

std::vector<std::pair<std::string, FrameMode>> families(const StudyReport& r) {
  std::vector<std::pair<std::string, FrameMode>> out;
  for (const Run& run : r.runs) {
    const auto f = std::make_pair(run.config.selector, run.config.mode);
    if (std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
  }
  return out;
}

std::string htmlEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

}  // namespace

std::string studyJson(const StudyReport& r, const Answers& a) {
  nlohmann::json runs = nlohmann::json::array();
  for (const Run& run : r.runs) {
    nlohmann::json frames = nlohmann::json::array();
    for (const FrameResult& f : run.frames)
      frames.push_back({{"frame", f.frame},
                        {"time", f.time},
                        {"frameMs", f.frameMs},
                        {"queryGpuMs", f.queryGpuMs},
                        {"triangles", f.triangles},
                        {"psnr", finiteOr(f.psnr, kMaxPsnr)},
                        {"ssim", f.ssim},
                        {"flip", f.flip},
                        {"coverage", f.coverage},
                        {"sseMaxPx", f.sseMaxPx},
                        {"sseMeanPx", f.sseMeanPx},
                        {"toggles", f.toggles},
                        {"bytesLoaded", f.bytesLoaded}});
    nlohmann::json j = configJson(run.config);
    j["summary"] = summaryJson(run.summary);
    j["onParetoFront"] = run.onParetoFront;
    j["frames"] = frames;
    runs.push_back(j);
  }
  nlohmann::json reference = nlohmann::json::array();
  for (const ReferenceFrame& f : r.reference)
    reference.push_back(
        {{"frame", f.frame}, {"time", f.time}, {"frameMs", f.frameMs}, {"triangles", f.triangles}});
  nlohmann::json equal = nlohmann::json::array();
  for (const auto& e : a.lakhiaVsSse)
    equal.push_back({{"budgetMs", e.budgetMs},
                     {"lakhiaMs", e.lakhiaMs},
                     {"lakhiaPsnr", e.lakhiaPsnr},
                     {"ssePsnr", std::isfinite(e.ssePsnr) ? nlohmann::json(e.ssePsnr) : nullptr},
                     {"gainDb", std::isfinite(e.gainDb) ? nlohmann::json(e.gainDb) : nullptr},
                     {"lakhiaDominatedBySse", e.lakhiaDominatedBySse}});
  nlohmann::json slopes = nlohmann::json::array();
  for (const auto& s : a.dbPerMs)
    slopes.push_back({{"selector", s.selector},
                      {"from", s.fromBudget},
                      {"to", s.toBudget},
                      {"fromMs", s.fromMs},
                      {"toMs", s.toMs},
                      {"dbPerMs", std::isfinite(s.dbPerMs) ? nlohmann::json(s.dbPerMs) : nullptr}});
  nlohmann::json answers = {{"lakhiaVsSseAtEqualTime", equal},
                            {"dbPerExtraMs", slopes},
                            {"lakhiaNear33",
                             {{"budgetMs", a.lakhia33Budget},
                              {"medianPsnr", a.lakhia33MedianPsnr},
                              {"worstPsnr", a.lakhia33WorstPsnr},
                              {"worstFrame", a.lakhia33WorstFrame},
                              {"maxCoverage", a.lakhia33MaxCoverage},
                              {"framesOverCoverage", a.lakhia33FramesOverCoverage}}},
                            {"sentences", a.lines()}};
  return nlohmann::json{
      {"settings", r.settings}, {"reference", reference}, {"runs", runs}, {"answers", answers}}
      .dump(1);
}

std::string studyCsv(const StudyReport& r) {
  std::ostringstream o;
  o << "label,selector,mode,budgetMs,ssePx,frame,time,frameMs,queryGpuMs,triangles,psnr,ssim,flip,"
       "coverage,sseMaxPx,sseMeanPx,toggles,bytesLoaded\n";
  for (const Run& run : r.runs) {
    const StudyConfig& c = run.config;
    for (const FrameResult& f : run.frames) {
      o << '"' << c.label() << "\"," << c.selector << ','
        << (c.mode == FrameMode::Settled ? "settled" : "realtime") << ','
        << (c.selector == "sse" ? 0.0 : c.budgetMs) << ',' << (c.selector == "sse" ? c.ssePx : 0.0)
        << ',' << f.frame << ',' << f.time << ',' << f.frameMs << ',' << f.queryGpuMs << ','
        << f.triangles << ',' << finiteOr(f.psnr, kMaxPsnr) << ',' << f.ssim << ',' << f.flip << ','
        << f.coverage << ',' << f.sseMaxPx << ',' << f.sseMeanPx << ',' << f.toggles << ','
        << f.bytesLoaded << '\n';
    }
  }
  return o.str();
}

std::string paretoSvg(const StudyReport& r, bool flip) {
  PlotSpec spec;
  spec.title = flip ? "Perceptual error (FLIP) against frame time"
                    : "Image error against frame time (Pareto front dashed)";
  spec.xLabel = "mean frame time (ms)";
  spec.yLabel = flip ? "mean FLIP (lower is better)" : "median PSNR against full detail (dB)";
  spec.yFromZero = false;
  spec.xFromZero = true;
  spec.width = 960;
  spec.height = 540;
  for (const auto& [selector, mode] : families(r)) {
    PlotSeries s;
    s.name = selector + (mode == FrameMode::Realtime ? " realtime" : "");
    s.color = colorOf(selector);
    s.dashed = mode == FrameMode::Realtime;
    s.marker = 4.0;
    for (const Run* run : family(r, selector, mode)) {
      s.x.push_back(run->summary.meanMs);
      s.y.push_back(flip ? run->summary.meanFlip : run->summary.medianPsnr);
      s.labels.push_back(selector == "sse" ? fmt("%gpx", run->config.ssePx)
                                           : fmt("%gms", run->config.budgetMs));
    }
    spec.series.push_back(std::move(s));
  }
  if (!flip) {
    PlotSeries front;
    front.name = "Pareto front";
    front.color = "#000";
    front.dashed = true;
    front.width = 1.0;
    std::vector<const Run*> onFront;
    for (const Run& run : r.runs)
      if (run.onParetoFront) onFront.push_back(&run);
    std::sort(onFront.begin(), onFront.end(),
              [](const Run* a, const Run* b) { return a->summary.meanMs < b->summary.meanMs; });
    for (const Run* run : onFront) {
      front.x.push_back(run->summary.meanMs);
      front.y.push_back(run->summary.medianPsnr);
    }
    spec.series.push_back(std::move(front));
  }
  return lineChartSvg(spec);
}

std::string pathSvg(const StudyReport& r) {
  PlotSpec spec;
  spec.title = "Image error over the path";
  spec.xLabel = "path time (s)";
  spec.yLabel = "PSNR against full detail (dB)";
  spec.yFromZero = false;
  spec.width = 960;
  spec.height = 480;
  std::size_t lakhia = 0, sse = 0;
  for (const Run& run : r.runs) {
    if (run.config.mode != FrameMode::Settled) continue;
    if (run.config.selector != "lakhia" && run.config.selector != "sse") continue;
    PlotSeries s;
    s.name = run.config.label();
    const bool isSse = run.config.selector == "sse";
    s.color = kColors[(isSse ? 5 + sse++ : lakhia++) % 10];
    s.dashed = isSse;
    s.width = isSse ? 1.0 : 1.8;
    for (const FrameResult& f : run.frames) {
      s.x.push_back(f.time);
      s.y.push_back(finiteOr(f.psnr, kMaxPsnr));
    }
    spec.series.push_back(std::move(s));
  }
  return lineChartSvg(spec);
}

std::string dbPerMsSvg(const Answers& a) {
  PlotSpec spec;
  spec.title = "What one more millisecond buys";
  spec.xLabel = "mean frame time at the start of the step (ms)";
  spec.yLabel = "dB of median PSNR per extra ms";
  spec.zeroLine = true;
  spec.width = 960;
  spec.height = 420;
  std::map<std::string, PlotSeries> bySelector;
  for (const auto& s : a.dbPerMs) {
    if (!std::isfinite(s.dbPerMs)) continue;
    PlotSeries& p = bySelector[s.selector];
    p.name = s.selector;
    const std::string base = s.selector.substr(0, s.selector.find(' '));
    p.color = colorOf(base);
    p.dashed = s.selector.find("realtime") != std::string::npos;
    p.marker = 4.0;
    p.x.push_back(s.fromMs);
    p.y.push_back(s.dbPerMs);
    p.labels.push_back(fmt("%g", s.fromBudget) + "->" + fmt("%g", s.toBudget));
  }
  for (auto& [name, p] : bySelector) spec.series.push_back(std::move(p));
  return lineChartSvg(spec);
}

std::string studyHtml(const StudyReport& r, const Answers& a) {
  std::ostringstream o;
  o << "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
    << "<title>hlodr accuracy study</title>\n<style>\n"
    << "body{font-family:system-ui,sans-serif;margin:24px auto;max-width:1100px;color:#222;"
       "line-height:1.45}\n"
    << "table{border-collapse:collapse;font-size:13px}td,th{border-bottom:1px solid #ddd;"
       "padding:3px 8px;text-align:right}th{background:#f4f4f4}td:first-child,th:first-child{"
       "text-align:left}\n"
    << "img{max-width:100%;border:1px solid #ddd;margin:6px 0}li{margin:2px 0}"
       "code{background:#f4f4f4;padding:1px 4px}\n</style></head><body>\n"
    << "<h1>What accuracy costs in time</h1>\n<p>";
  for (auto it = r.settings.begin(); it != r.settings.end(); ++it)
    o << "<code>" << htmlEscape(it.key()) << "</code> " << htmlEscape(it.value().dump())
      << " &nbsp; ";
  o << "</p>\n<h2>Answers</h2>\n<ul>\n";
  for (const auto& line : a.lines()) o << "<li>" << htmlEscape(line) << "</li>\n";
  o << "</ul>\n<h2>Error against frame time</h2>\n<img src=\"pareto.svg\" alt=\"pareto\">\n"
    << "<img src=\"flip.svg\" alt=\"flip\">\n<h2>Over the path</h2>\n"
    << "<img src=\"path.svg\" alt=\"path\">\n<h2>What one more millisecond buys</h2>\n"
    << "<img src=\"db-per-ms.svg\" alt=\"dB per ms\">\n<h2>Frames</h2>\n";
  for (std::size_t i = 0; i < r.strips.size(); ++i)
    o << "<p>" << htmlEscape(i < r.stripCaptions.size() ? r.stripCaptions[i] : "") << "</p>\n"
      << "<img src=\"" << htmlEscape(r.strips[i]) << "\" alt=\"strip\">\n";
  o << "<h2>Runs</h2>\n<table><tr><th>run</th><th>mean ms</th><th>p95 ms</th>"
       "<th>triangles</th><th>median dB</th><th>worst dB</th><th>SSIM</th><th>FLIP</th>"
       "<th>max coverage %</th><th>SSE px</th><th>toggles/frame</th><th>MB loaded</th>"
       "<th>Pareto</th></tr>\n";
  for (const Run& run : r.runs) {
    const RunSummary& s = run.summary;
    o << "<tr><td>" << htmlEscape(run.config.label()) << "</td><td>" << fmt("%.1f", s.meanMs)
      << "</td><td>" << fmt("%.1f", s.p95Ms) << "</td><td>" << fmt("%.0f", s.meanTriangles)
      << "</td><td>" << fmt("%.2f", s.medianPsnr) << "</td><td>" << fmt("%.2f", s.worstPsnr)
      << "</td><td>" << fmt("%.4f", s.meanSsim) << "</td><td>" << fmt("%.4f", s.meanFlip)
      << "</td><td>" << fmt("%.2f", 100.0 * s.maxCoverage) << "</td><td>"
      << fmt("%.1f", s.meanSseMaxPx) << "</td><td>" << fmt("%.2f", s.togglesPerFrame) << "</td><td>"
      << fmt("%.1f", double(s.bytesLoaded) / 1e6) << "</td><td>" << (run.onParetoFront ? "yes" : "")
      << "</td></tr>\n";
  }
  double refMs = 0.0, refTri = 0.0;
  for (const auto& f : r.reference) refMs += f.frameMs, refTri += double(f.triangles);
  if (!r.reference.empty())
    o << "<tr><td>full detail (reference)</td><td>" << fmt("%.1f", refMs / r.reference.size())
      << "</td><td></td><td>" << fmt("%.0f", refTri / r.reference.size())
      << "</td><td colspan=\"10\"></td></tr>\n";
  o << "</table>\n<p>Files: <a href=\"study.json\">study.json</a>, "
       "<a href=\"study.csv\">study.csv</a>.</p>\n</body></html>\n";
  return o.str();
}

Status writeStudyReport(const std::filesystem::path& dir, const StudyReport& report) {
  const Answers a = answer(report.runs);
  const std::pair<const char*, std::string> files[] = {
      {"study.json", studyJson(report, a) + "\n"},
      {"study.csv", studyCsv(report)},
      {"pareto.svg", paretoSvg(report, false)},
      {"flip.svg", paretoSvg(report, true)},
      {"path.svg", pathSvg(report)},
      {"db-per-ms.svg", dbPerMsSvg(a)},
      {"index.html", studyHtml(report, a)},
  };
  for (const auto& [name, text] : files) {
    const auto path = dir / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) return makeError("cannot write " + path.string());
  }
  return Ok{};
}

Image composeGrid(const std::vector<Image>& cells, int columns, int cellWidth, int cellHeight) {
  assert(columns > 0 && cellWidth > 0 && cellHeight > 0);
  const int rows = static_cast<int>((cells.size() + columns - 1) / columns);
  Image out;
  out.width = columns * cellWidth;
  out.height = std::max(1, rows) * cellHeight;
  out.pixels.assign(static_cast<std::size_t>(out.width) * out.height * 4, 255);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const Image& src = cells[i];
    if (src.empty()) continue;
    const int cx = static_cast<int>(i % columns) * cellWidth;
    const int cy = static_cast<int>(i / columns) * cellHeight;
    // Box filter: each target pixel averages the source pixels it covers.
    for (int y = 0; y < cellHeight; ++y) {
      const int sy0 = y * src.height / cellHeight;
      const int sy1 = std::max(sy0 + 1, (y + 1) * src.height / cellHeight);
      for (int x = 0; x < cellWidth; ++x) {
        const int sx0 = x * src.width / cellWidth;
        const int sx1 = std::max(sx0 + 1, (x + 1) * src.width / cellWidth);
        unsigned sum[4] = {0, 0, 0, 0}, n = 0;
        for (int sy = sy0; sy < sy1; ++sy)
          for (int sx = sx0; sx < sx1; ++sx, ++n)
            for (int c = 0; c < 4; ++c)
              sum[c] += src.pixels[(static_cast<std::size_t>(sy) * src.width + sx) * 4 + c];
        std::uint8_t* d = &out.pixels[(static_cast<std::size_t>(cy + y) * out.width + cx + x) * 4];
        for (int c = 0; c < 4; ++c) d[c] = static_cast<std::uint8_t>(sum[c] / n);
      }
    }
  }
  return out;
}

}  // namespace hlod::study
