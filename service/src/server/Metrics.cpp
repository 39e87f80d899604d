#include "server/Metrics.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace service::server {

namespace {

std::string number(double v) {
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  if (std::isnan(v)) return "NaN";
  // The shortest form that reads back as the same double (0.033, not 0.033000000000000002).
  char buf[64];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string withLabels(const std::string& name, const std::string& labels) {
  return labels.empty() ? name : name + "{" + labels + "}";
}

}  // namespace

Histogram::Histogram(std::vector<double> upperBounds)
    : bounds_(std::move(upperBounds)), counts_(bounds_.size() + 1, 0) {}

void Histogram::observe(double value) {
  if (!std::isfinite(value)) return;
  std::lock_guard lock(mutex_);
  std::size_t i = 0;
  while (i < bounds_.size() && value > bounds_[i]) ++i;
  ++counts_[i];
  sum_ += value;
  ++count_;
}

void Histogram::write(std::string& out, const std::string& name, const std::string& labels) const {
  std::lock_guard lock(mutex_);
  const std::string sep = labels.empty() ? "" : labels + ",";
  std::uint64_t cumulative = 0;
  for (std::size_t i = 0; i <= bounds_.size(); ++i) {
    cumulative += counts_[i];
    const std::string le = i < bounds_.size() ? number(bounds_[i]) : "+Inf";
    out += name + "_bucket{" + sep + "le=\"" + le + "\"} " + std::to_string(cumulative) + "\n";
  }
  out += withLabels(name + "_sum", labels) + " " + number(sum_) + "\n";
  out += withLabels(name + "_count", labels) + " " + std::to_string(count_) + "\n";
}

Metrics::Metrics()
    // Frame times around the usual budgets (8, 16, 33, 66, 133 ms) and beyond.
    : frameSeconds_({0.004, 0.008, 0.016, 0.033, 0.05, 0.066, 0.1, 0.133, 0.25, 0.5, 1.0}),
      requestSeconds_({0.001, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 5.0, 10.0}) {}

void Metrics::add(const std::string& name, const std::string& labels, double value) {
  std::lock_guard lock(mutex_);
  counters_[name][labels] += value;
}

void Metrics::help(const std::string& name, const std::string& text) {
  std::lock_guard lock(mutex_);
  help_[name] = text;
}

void Metrics::gauge(const std::string& name, const std::string& help, const std::string& type,
                    std::function<std::vector<std::pair<std::string, double>>()> read) {
  std::lock_guard lock(mutex_);
  gauges_[name] = {help, type, std::move(read)};
}

std::string Metrics::text() const {
  std::string out;
  std::map<std::string, std::map<std::string, double>> counters;
  std::map<std::string, std::string> help;
  std::map<std::string, Gauge> gauges;
  {
    std::lock_guard lock(mutex_);
    counters = counters_;
    help = help_;
    gauges = gauges_;
  }
  for (const auto& [name, series] : counters) {
    out += "# HELP " + name + " " + (help.count(name) ? help[name] : name) + "\n";
    out += "# TYPE " + name + " counter\n";
    for (const auto& [labels, v] : series) out += withLabels(name, labels) + " " + number(v) + "\n";
  }
  for (const auto& [name, g] : gauges) {
    out += "# HELP " + name + " " + g.help + "\n";
    out += "# TYPE " + name + " " + g.type + "\n";
    for (const auto& [labels, v] : g.read())
      out += withLabels(name, labels) + " " + number(v) + "\n";
  }
  out += "# HELP hlodr_frame_seconds Frame time (GL work through glFinish, uploads included)\n";
  out += "# TYPE hlodr_frame_seconds histogram\n";
  frameSeconds_.write(out, "hlodr_frame_seconds", "");
  out += "# HELP hlodr_http_request_duration_seconds Time from request to response\n";
  out += "# TYPE hlodr_http_request_duration_seconds histogram\n";
  requestSeconds_.write(out, "hlodr_http_request_duration_seconds", "");
  return out;
}

}  // namespace service::server
