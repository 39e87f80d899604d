#pragma once
// The server's figures in the Prometheus text exposition format (version 0.0.4): counters end in
// _total, durations are seconds, sizes bytes, names start with hlodr_. Thread-safe; gauges are
// read through callbacks when /metrics is scraped.
#include <atomic>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace service::server {

class Histogram {
 public:
  explicit Histogram(std::vector<double> upperBounds);
  void observe(double value);
  // The _bucket, _sum and _count lines of `name` with `labels` (e.g. `kind="job"`, or "").
  void write(std::string& out, const std::string& name, const std::string& labels) const;

 private:
  std::vector<double> bounds_;
  mutable std::mutex mutex_;
  std::vector<std::uint64_t> counts_;  // per bucket (not cumulative), +Inf last
  double sum_ = 0.0;
  std::uint64_t count_ = 0;
};

class Metrics {
 public:
  Metrics();
  // A counter with one set of label values, e.g. ("hlodr_frames_total", "kind=\"job\"").
  void add(const std::string& name, const std::string& labels, double value = 1.0);
  void observeFrame(double seconds) { frameSeconds_.observe(seconds); }
  void observeRequest(double seconds) { requestSeconds_.observe(seconds); }
  // A gauge (or counter read from elsewhere) sampled at scrape time; type "gauge" or "counter".
  void gauge(const std::string& name, const std::string& help, const std::string& type,
             std::function<std::vector<std::pair<std::string, double>>()> read);
  void help(const std::string& name, const std::string& text);
  std::string text() const;

 private:
  struct Gauge {
    std::string help, type;
    std::function<std::vector<std::pair<std::string, double>>()> read;
  };
  mutable std::mutex mutex_;
  std::map<std::string, std::map<std::string, double>> counters_;
  std::map<std::string, std::string> help_;
  std::map<std::string, Gauge> gauges_;
  Histogram frameSeconds_;
  Histogram requestSeconds_;
};

}  // namespace service::server
