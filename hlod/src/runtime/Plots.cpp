#include "hlod/runtime/Plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace hlod {

namespace {

const char* kPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                          "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

std::string tickLabel(double v, double step) {
  char buf[32];
  const int decimals = step >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  std::snprintf(buf, sizeof buf, "%.*f", std::clamp(decimals, 0, 6),
                std::abs(v) < step * 1e-6 ? 0.0 : v);
  return buf;
}

// Tick spacing of 1, 2 or 5 times a power of ten giving about `count` intervals.
double niceStep(double range, int count) {
  if (!(range > 0.0) || !std::isfinite(range)) return 1.0;
  const double raw = range / count;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * p >= raw) return m * p;
  }
  return 10.0 * p;
}

PlotSeries lineSeries(std::string name, std::string color, std::vector<double> x,
                      std::vector<double> y, double width, double opacity, bool dashed) {
  PlotSeries s;
  s.name = std::move(name);
  s.color = std::move(color);
  s.x = std::move(x);
  s.y = std::move(y);
  s.width = width;
  s.opacity = opacity;
  s.dashed = dashed;
  return s;
}

std::vector<double> indexX(std::span<const FrameRecord> frames) {
  std::vector<double> x;
  for (const FrameRecord& f : frames) x.push_back(static_cast<double>(f.index));
  return x;
}

}  // namespace

std::vector<double> movingAverage(std::span<const double> values, int window) {
  std::vector<double> out(values.size(), 0.0);
  const std::size_t w = static_cast<std::size_t>(std::max(1, window));
  double sum = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    sum += values[i];
    if (i >= w) sum -= values[i - w];
    out[i] = sum / static_cast<double>(std::min(i + 1, w));
  }
  return out;
}

std::string lineChartSvg(const PlotSpec& spec) {
  const double W = std::max(200, spec.width), H = std::max(150, spec.height);
  // The legend sits right of the plot: room for its longest name (about 7.5 px a character).
  std::size_t longest = 0;
  for (const PlotSeries& s : spec.series) longest = std::max(longest, s.name.size());
  const double left = 70, right = std::max(120.0, 55.0 + 7.5 * double(longest)), top = 40,
               bottom = 55;
  const double pw = W - left - right, ph = H - top - bottom;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const PlotSeries& s : spec.series) {
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x0 = std::min(x0, s.x[i]);
      x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, s.y[i]);
      y1 = std::max(y1, s.y[i]);
    }
  }
  if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;  // no data
  if (spec.zeroLine || (spec.yFromZero && y0 > 0.0)) y0 = std::min(y0, 0.0);
  if (spec.xFromZero && x0 > 0.0) x0 = 0.0;
  if (!spec.yFromZero && y1 - y0 > 0.0) {
    const double pad = (y1 - y0) * 0.05;  // markers at the extremes stay inside the frame
    y0 -= pad;
    y1 += pad;
  }
  if (y1 < 0.0 && spec.zeroLine) y1 = 0.0;
  if (x1 - x0 <= 0.0) x1 = x0 + 1.0;
  if (y1 - y0 <= 0.0) y1 = y0 + 1.0;
  const double xs = niceStep(x1 - x0, 8), ys = niceStep(y1 - y0, 6);
  y0 = std::floor(y0 / ys) * ys;
  y1 = std::ceil(y1 / ys) * ys;
  auto X = [&](double v) { return left + (v - x0) / (x1 - x0) * pw; };
  auto Y = [&](double v) { return top + ph - (v - y0) / (y1 - y0) * ph; };

  std::ostringstream o;
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << W << "\" height=\""
    << H << "\" viewBox=\"0 0 " << W << ' ' << H
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << num(left + pw / 2) << "\" y=\"24\" text-anchor=\"middle\" font-size=\"16\">"
    << escape(spec.title) << "</text>\n";
  // Grid and ticks.
  for (double v = std::ceil(x0 / xs) * xs; v <= x1 + xs * 1e-9; v += xs) {
    o << "<line x1=\"" << num(X(v)) << "\" y1=\"" << num(top) << "\" x2=\"" << num(X(v))
      << "\" y2=\"" << num(top + ph + 5) << "\" stroke=\"#ddd\"/>\n"
      << "<text x=\"" << num(X(v)) << "\" y=\"" << num(top + ph + 18)
      << "\" text-anchor=\"middle\">" << tickLabel(v, xs) << "</text>\n";
  }
  for (double v = y0; v <= y1 + ys * 1e-9; v += ys) {
    o << "<line x1=\"" << num(left - 5) << "\" y1=\"" << num(Y(v)) << "\" x2=\"" << num(left + pw)
      << "\" y2=\"" << num(Y(v)) << "\" stroke=\"#ddd\"/>\n"
      << "<text x=\"" << num(left - 8) << "\" y=\"" << num(Y(v) + 4) << "\" text-anchor=\"end\">"
      << tickLabel(v, ys) << "</text>\n";
  }
  if (spec.zeroLine) {
    o << "<line x1=\"" << num(left) << "\" y1=\"" << num(Y(0)) << "\" x2=\"" << num(left + pw)
      << "\" y2=\"" << num(Y(0)) << "\" stroke=\"#444\"/>\n";
  }
  o << "<rect x=\"" << num(left) << "\" y=\"" << num(top) << "\" width=\"" << num(pw)
    << "\" height=\"" << num(ph) << "\" fill=\"none\" stroke=\"#333\"/>\n";
  o << "<text x=\"" << num(left + pw / 2) << "\" y=\"" << num(H - 12)
    << "\" text-anchor=\"middle\">" << escape(spec.xLabel) << "</text>\n"
    << "<text transform=\"translate(18," << num(top + ph / 2)
    << ") rotate(-90)\" text-anchor=\"middle\">" << escape(spec.yLabel) << "</text>\n";
  // Series.
  for (const PlotSeries& s : spec.series) {
    std::ostringstream pts;
    std::size_t n = 0;
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      pts << (n++ ? " " : "") << num(X(s.x[i])) << ',' << num(Y(s.y[i]));
    }
    if (n == 0) continue;
    if (s.line)
      o << "<polyline fill=\"none\" stroke=\"" << escape(s.color) << "\" stroke-width=\""
        << num(s.width) << "\" stroke-opacity=\"" << num(s.opacity) << "\""
        << (s.dashed ? " stroke-dasharray=\"6,4\"" : "") << " points=\"" << pts.str() << "\"/>\n";
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      if (s.marker > 0.0)
        o << "<circle cx=\"" << num(X(s.x[i])) << "\" cy=\"" << num(Y(s.y[i])) << "\" r=\""
          << num(s.marker) << "\" fill=\"" << escape(s.color) << "\" fill-opacity=\""
          << num(s.opacity) << "\"/>\n";
      if (i < s.labels.size() && !s.labels[i].empty())
        o << "<text x=\"" << num(X(s.x[i]) + s.marker + 3) << "\" y=\"" << num(Y(s.y[i]) - 4)
          << "\" font-size=\"10\" fill=\"#333\">" << escape(s.labels[i]) << "</text>\n";
    }
  }
  // Legend.
  double ly = top + 10;
  for (const PlotSeries& s : spec.series) {
    const double lx = left + pw + 15;
    if (s.line)
      o << "<line x1=\"" << num(lx) << "\" y1=\"" << num(ly) << "\" x2=\"" << num(lx + 24)
        << "\" y2=\"" << num(ly) << "\" stroke=\"" << escape(s.color) << "\" stroke-width=\""
        << num(std::max(2.0, s.width)) << "\"" << (s.dashed ? " stroke-dasharray=\"6,4\"" : "")
        << "/>\n";
    if (s.marker > 0.0 || !s.line)
      o << "<circle cx=\"" << num(lx + 12) << "\" cy=\"" << num(ly) << "\" r=\""
        << num(std::max(3.0, s.marker)) << "\" fill=\"" << escape(s.color) << "\"/>\n";
    o << "<text x=\"" << num(lx + 30) << "\" y=\"" << num(ly + 4) << "\">" << escape(s.name)
      << "</text>\n";
    ly += 18;
  }
  o << "</svg>\n";
  return o.str();
}

std::string levelsSvg(std::span<const FrameRecord> frames, const std::string& title) {
  PlotSpec spec;
  spec.title = title;
  spec.xLabel = "frame";
  spec.yLabel = "HLOD nodes drawn";
  std::size_t levels = 0;
  for (const FrameRecord& f : frames) levels = std::max(levels, f.nodesPerLevel.size());
  const std::vector<double> x = indexX(frames);
  for (std::size_t l = 0; l < levels; ++l) {
    PlotSeries s;
    s.name = "hlod_" + std::to_string(l);
    s.color = kPalette[l % std::size(kPalette)];
    s.x = x;
    for (const FrameRecord& f : frames) {
      s.y.push_back(l < f.nodesPerLevel.size() ? f.nodesPerLevel[l] : 0.0);
    }
    spec.series.push_back(std::move(s));
  }
  return lineChartSvg(spec);
}

std::string togglesSvg(std::span<const FrameRecord> frames, int window, const std::string& title) {
  PlotSpec spec;
  spec.title = title;
  spec.xLabel = "frame";
  spec.yLabel = "toggles per frame (down < 0)";
  spec.zeroLine = true;
  const std::vector<double> x = indexX(frames);
  std::vector<double> up, down;
  for (const FrameRecord& f : frames) {
    up.push_back(f.upToggles);
    down.push_back(-static_cast<double>(f.downToggles));
  }
  spec.series.push_back(lineSeries("up", "#2ca02c", x, up, 1.0, 0.35, false));
  spec.series.push_back(lineSeries("down", "#d62728", x, down, 1.0, 0.35, false));
  const std::string avg = " (" + std::to_string(std::max(1, window)) + "-frame avg)";
  spec.series.push_back(
      lineSeries("up" + avg, "#1a6e1a", x, movingAverage(up, window), 2.5, 1.0, false));
  spec.series.push_back(
      lineSeries("down" + avg, "#8b1a1a", x, movingAverage(down, window), 2.5, 1.0, false));
  return lineChartSvg(spec);
}

std::string frameTimeSvg(std::span<const FrameRecord> frames, const std::string& title) {
  PlotSpec spec;
  spec.title = title;
  spec.xLabel = "frame";
  spec.yLabel = "milliseconds";
  const std::vector<double> x = indexX(frames);
  std::vector<double> actual, target, estimated;
  for (const FrameRecord& f : frames) {
    actual.push_back(f.gpuMs);
    target.push_back(f.targetMs);
    estimated.push_back(f.estimatedMs);
  }
  spec.series.push_back(lineSeries("actual", "#1f77b4", x, actual, 1.5, 1.0, false));
  spec.series.push_back(lineSeries("target", "#d62728", x, target, 2.0, 1.0, true));
  spec.series.push_back(lineSeries("estimated", "#7f7f7f", x, estimated, 1.0, 0.8, false));
  return lineChartSvg(spec);
}

Status writeSvg(const std::string& path, const std::string& svg) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return makeError("cannot write '" + path + "'");
  out << svg;
  if (!out) return makeError("error writing '" + path + "'");
  return Ok{};
}

}  // namespace hlod
