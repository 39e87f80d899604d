#pragma once
// Hand-written SVG charts of the per-frame statistics, after Lakhia sec. IV:
//   Fig. 7: HLODs drawn per level over the frames (one line per level),
//   Fig. 8: up toggles (positive) and down toggles (negative) with a 35-frame moving average,
//   Fig. 9: actual frame time (gpuMs) against the target, with the selector's estimate.
// Each chart has axes with ticks and labels, a legend and a title. No library: plain SVG 1.1.
#include <span>
#include <string>
#include <vector>

#include "hlod/Result.h"
#include "hlod/runtime/FrameStats.h"

namespace hlod {

struct PlotSeries {
  std::string name;
  std::string color;  // any SVG colour, e.g. "#1f77b4"
  std::vector<double> x, y;
  double width = 1.5;
  double opacity = 1.0;
  bool dashed = false;
  bool line = true;                 // false: markers only (a scatter)
  double marker = 0.0;              // radius of a circle at each point; 0: none
  std::vector<std::string> labels;  // optional, one per point, written beside its marker
};

struct PlotSpec {
  std::string title;
  std::string xLabel;
  std::string yLabel;
  std::vector<PlotSeries> series;
  int width = 960;
  int height = 480;
  bool zeroLine = false;  // a horizontal line at y = 0
  bool yFromZero = true;  // the y axis starts at 0 for positive data; false: fits the data
  bool xFromZero = false;
};

// A line chart; non-finite points are skipped. Always valid SVG, also with no data.
std::string lineChartSvg(const PlotSpec& spec);

std::string levelsSvg(std::span<const FrameRecord> frames,
                      const std::string& title = "HLODs drawn per level");
std::string togglesSvg(std::span<const FrameRecord> frames, int window = 35,
                       const std::string& title = "Up and down toggles");
std::string frameTimeSvg(std::span<const FrameRecord> frames,
                         const std::string& title = "Actual vs target frame time");

// Trailing moving average over `window` values (shorter at the start).
std::vector<double> movingAverage(std::span<const double> values, int window);

Status writeSvg(const std::string& path, const std::string& svg);

}  // namespace hlod
