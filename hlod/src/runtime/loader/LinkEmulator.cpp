// The emulated link between the loader and its store (runtime/loader/LinkEmulator.h).
#include "runtime/loader/LinkEmulator.h"

#include <algorithm>
#include <utility>

namespace hlod {

LinkEmulator::LinkEmulator(double mbps, double latencyMs, std::size_t requests,
                           std::shared_ptr<LinkClock> clock)
    : mbps_(mbps),
      latencyMs_(latencyMs),
      requests_(requests),
      clock_(clock ? std::move(clock) : std::make_shared<SteadyLinkClock>()) {}

double LinkEmulator::seconds(std::uint64_t bytes, std::size_t requests) const {
  return static_cast<double>(bytes) * 8.0 / (mbps_ * 1e6) +
         latencyMs_ * 1e-3 * static_cast<double>(requests);
}

std::size_t LinkEmulator::window() const {
  return std::max<std::size_t>(1, requests_) - 1;
}

void LinkEmulator::requestAhead(std::uint32_t chosen, std::span<const std::uint32_t> ahead) {
  const LinkClock::TimePoint now = clock_->now();
  std::unordered_map<std::uint32_t, LinkClock::TimePoint> kept;
  for (std::uint32_t n : ahead) {
    auto it = ahead_.find(n);
    kept.emplace(n, it != ahead_.end() ? it->second : now);
  }
  // The chosen node keeps its request's time until its first read is served.
  if (auto it = ahead_.find(chosen); it != ahead_.end()) kept.insert(*it);
  ahead_.swap(kept);
}

void LinkEmulator::cancelAhead() {
  ahead_.clear();
}

bool LinkEmulator::continues(std::uint64_t at, std::size_t len) {
  const bool same = at == streamEnd_;
  streamEnd_ = at + len;
  return same;
}

double LinkEmulator::latencyMs(std::uint32_t node, LinkClock::TimePoint now) {
  double ms = std::max(0.0, latencyMs_);
  if (auto it = ahead_.find(node); it != ahead_.end()) {
    ms = std::max(0.0, ms - LinkClock::Milliseconds(now - it->second).count());
    ahead_.erase(it);
  }
  return ms;
}

double LinkEmulator::transferMs(std::size_t len) const {
  return mbps_ > 0.0 ? static_cast<double>(len) * 8.0 / (mbps_ * 1e3) : 0.0;
}

}  // namespace hlod
