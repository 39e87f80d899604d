// SelectorParams by name: `hlodr render --params c_aim=1,c_fillAdd=0.03`, walk_bench --params.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>

#include "hlod/runtime/Selector.h"

namespace hlod {
namespace {

// Every constant of SelectorParams by the name it has in the code (and the paper), with the
// range where it means what its comment in Selector.h says: a value outside is an Error that
// names the constant and its range (the selectors used to clamp such values silently where
// they used them). c_targetTime is not here: --budget-ms sets it.
struct Named {
  std::string_view name;
  double lo, hi;
  double LakhiaParams::*member = nullptr;
};
constexpr Named kLakhiaDoubles[] = {
    {"c_vis", 0.0, 100.0, &LakhiaParams::c_vis},
    {"c_visFalloff", 0.0, 100.0, &LakhiaParams::c_visFalloff},
    {"c_fore", 0.0, 0.99, &LakhiaParams::c_fore},  // foreshorten = 1 + facing * c_fore > 0
    {"c_velocity", 0.0, 10.0, &LakhiaParams::c_velocity},
    {"c_minDistance", 1e-6, 1e6, &LakhiaParams::c_minDistance},
    {"c_minCost", 1e-6, 1e9, &LakhiaParams::c_minCost},
    {"c_hystLimit", 0.0, 1000.0, &LakhiaParams::c_hystLimit},
    {"c_hystSwitch", 1e-3, 1000.0, &LakhiaParams::c_hystSwitch},
    {"c_hystInitial", -1000.0, 1000.0, &LakhiaParams::c_hystInitial},
    {"vTimeInitial", 1e-12, 1e3, &LakhiaParams::vTimeInitial},
    {"feedbackGain", 1e-3, 1.0, &LakhiaParams::feedbackGain},  // 0 < gain <= 1: no overshoot
    {"feedbackMaxRatio", 1.0, 1000.0, &LakhiaParams::feedbackMaxRatio},
    {"feedbackJumpRatio", 0.0, 1000.0, &LakhiaParams::feedbackJumpRatio},  // 0: off
    {"c_shed", 0.0, 100.0, &LakhiaParams::c_shed},
    {"c_errorBenefit", -1.0, 1.0, &LakhiaParams::c_errorBenefit},
    {"c_demandMargin", 1.0, 100.0, &LakhiaParams::c_demandMargin},
    {"c_aim", 0.1, 1.5, &LakhiaParams::c_aim},
    {"c_fillKeep", 0.0, 1.0, &LakhiaParams::c_fillKeep},
    {"c_fillAdd", 0.0, 0.9, &LakhiaParams::c_fillAdd},
    {"c_fillFast", 0.0, 1.0, &LakhiaParams::c_fillFast},
    {"c_fillGain", 0.0, 1.0, &LakhiaParams::c_fillGain},
};
// The rest: an integer, numbers of SelectorParams itself, and switches (0 or 1).
constexpr Named kOthers[] = {
    {"c_hystRefine", 0.0, 1e6}, {"ssePixels", 0.1, 1000.0},    {"splatPixels", 0.0, 10000.0},
    {"c_splat", 0.0, 1000.0},   {"quadtreeCulling", 0.0, 1.0}, {"splats", 0.0, 1.0},
    {"progressive", 0.0, 1.0},  {"c_occludedLoad", 0.0, 1.0},  {"c_occludedKeepFrames", 0.0, 1e6},
};

bool isSwitch(std::string_view name) {
  return name == "quadtreeCulling" || name == "splats" || name == "progressive";
}

const Named* find(std::string_view name) {
  for (const Named& n : kLakhiaDoubles)
    if (n.name == name) return &n;
  for (const Named& n : kOthers)
    if (n.name == name) return &n;
  return nullptr;
}

// Shortest readable: 1.5, not 1.500000.
std::string numberText(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string rangeText(const Named& n) {
  return numberText(n.lo) + ".." + numberText(n.hi);
}

}  // namespace

std::string selectorParamNames() {
  std::string names;
  for (const Named& n : kLakhiaDoubles) names += std::string(n.name) + ' ';
  for (const Named& n : kOthers) names += std::string(n.name) + ' ';
  names.pop_back();
  return names;
}

Status setSelectorParam(SelectorParams& params, std::string_view name, double value) {
  const Named* n = find(name);
  if (!n)
    return makeError("unknown parameter '" + std::string(name) +
                     "' (known: " + selectorParamNames() + ")");
  // c_hystRefine is a count; the switches are 0 or 1.
  const bool whole = name == "c_hystRefine" || isSwitch(name);
  if (!std::isfinite(value) || value < n->lo || value > n->hi ||
      (whole && value != std::trunc(value)))
    return makeError("parameter " + std::string(name) + ": " +
                     (std::isfinite(value) ? numberText(value) : "not finite") +
                     " is outside its range " + rangeText(*n) + (whole ? " (a whole number)" : ""));
  if (n->member) {
    params.lakhia.*n->member = value;
  } else if (name == "c_hystRefine") {
    params.lakhia.c_hystRefine = static_cast<long long>(value);
  } else if (name == "ssePixels") {
    params.ssePixels = value;
  } else if (name == "splatPixels") {
    params.splatPixels = value;
  } else if (name == "c_splat") {
    params.c_splat = value;
  } else if (name == "quadtreeCulling") {
    params.quadtreeCulling = value == 1.0;
  } else if (name == "splats") {
    params.splats = value == 1.0;
  } else if (name == "c_occludedLoad") {
    params.c_occludedLoad = value;
  } else if (name == "c_occludedKeepFrames") {
    params.c_occludedKeepFrames = value;
  } else {
    params.progressive = value == 1.0;
  }
  return Ok{};
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
