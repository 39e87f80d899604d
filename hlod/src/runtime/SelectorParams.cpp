// SelectorParams by name: `hlodr render --params c_aim=1,c_fillAdd=0.03`, walk_bench --params.
#include <charconv>
#include <cmath>
#include <string>

#include "hlod/runtime/Selector.h"

namespace hlod {
namespace {

// Every tunable double of SelectorParams, with the name it has in the code (and the paper).
// c_targetTime is not here: --budget-ms sets it. c_hystRefine is an integer, handled apart.
struct Named {
  std::string_view name;
  double LakhiaParams::*member;
  bool signedValue = false;  // a hysteresis counter's start may be negative; nothing else
};
constexpr Named kLakhiaDoubles[] = {
    {"c_vis", &LakhiaParams::c_vis},
    {"c_visFalloff", &LakhiaParams::c_visFalloff},
    {"c_fore", &LakhiaParams::c_fore},
    {"c_velocity", &LakhiaParams::c_velocity},
    {"c_minDistance", &LakhiaParams::c_minDistance},
    {"c_minCost", &LakhiaParams::c_minCost},
    {"c_hystLimit", &LakhiaParams::c_hystLimit},
    {"c_hystSwitch", &LakhiaParams::c_hystSwitch},
    {"c_hystInitial", &LakhiaParams::c_hystInitial, true},
    {"vTimeInitial", &LakhiaParams::vTimeInitial},
    {"feedbackGain", &LakhiaParams::feedbackGain},
    {"feedbackMaxRatio", &LakhiaParams::feedbackMaxRatio},
    {"feedbackJumpRatio", &LakhiaParams::feedbackJumpRatio},
    {"c_shed", &LakhiaParams::c_shed},
    {"c_demandMargin", &LakhiaParams::c_demandMargin},
    {"c_aim", &LakhiaParams::c_aim},
    {"c_fillKeep", &LakhiaParams::c_fillKeep},
    {"c_fillAdd", &LakhiaParams::c_fillAdd},
    {"c_fillFast", &LakhiaParams::c_fillFast},
    {"c_fillGain", &LakhiaParams::c_fillGain},
};

}  // namespace

std::string selectorParamNames() {
  std::string names;
  for (const Named& n : kLakhiaDoubles) names += std::string(n.name) + ' ';
  return names + "c_hystRefine ssePixels quadtreeCulling splats splatPixels c_splat progressive";
}

Status setSelectorParam(SelectorParams& params, std::string_view name, double value) {
  if (!std::isfinite(value))
    return makeError("parameter " + std::string(name) + ": not a finite number");
  if (name == "ssePixels") {
    if (!(value > 0.0)) return makeError("parameter ssePixels: must be above 0");
    params.ssePixels = value;
    return Ok{};
  }
  if (name == "splats" || name == "progressive") {
    if (value != 0.0 && value != 1.0)
      return makeError("parameter " + std::string(name) + ": must be 0 or 1");
    (name == "splats" ? params.splats : params.progressive) = value == 1.0;
    return Ok{};
  }
  if (name == "splatPixels" || name == "c_splat") {
    if (!(value >= 0.0) || !std::isfinite(value))
      return makeError("parameter " + std::string(name) + ": must be finite and >= 0");
    (name == "splatPixels" ? params.splatPixels : params.c_splat) = value;
    return Ok{};
  }
  if (name == "quadtreeCulling") {
    if (value != 0.0 && value != 1.0) return makeError("parameter quadtreeCulling: must be 0 or 1");
    params.quadtreeCulling = value == 1.0;
    return Ok{};
  }
  if (name == "c_hystRefine") {
    if (value != std::trunc(value) || std::fabs(value) > 1e6)
      return makeError("parameter c_hystRefine: must be a whole number");
    params.lakhia.c_hystRefine = static_cast<long long>(value);
    return Ok{};
  }
  for (const Named& n : kLakhiaDoubles) {
    if (n.name == name) {
      // The selectors clamp each constant to its meaningful range where they use it.
      if (value < 0.0 && !n.signedValue)
        return makeError("parameter " + std::string(name) + ": must be >= 0");
      params.lakhia.*n.member = value;
      return Ok{};
    }
  }
  return makeError("unknown parameter '" + std::string(name) + "' (known: " + selectorParamNames() +
                   ")");
}

Status setSelectorParams(SelectorParams& params, std::string_view list) {
  SelectorParams set = params;  // all or nothing
  while (!list.empty()) {
    const std::size_t comma = list.find(',');
    const std::string_view item = list.substr(0, comma);
    list = comma == std::string_view::npos ? std::string_view{} : list.substr(comma + 1);
    const std::size_t eq = item.find('=');
    if (eq == std::string_view::npos || eq == 0)
      return makeError("parameter '" + std::string(item) + "': expected NAME=VALUE");
    const std::string_view text = item.substr(eq + 1);
    double value = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc{} || end != text.data() + text.size() || text.empty())
      return makeError("parameter '" + std::string(item) + "': value is not a number");
    if (auto s = setSelectorParam(set, item.substr(0, eq), value); !s) return s;
  }
  params = set;
  return Ok{};
}

}  // namespace hlod
