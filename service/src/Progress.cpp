#include "service/Progress.h"

#include <unistd.h>

#include <cstdio>

namespace service {

ProgressLine::ProgressLine(std::string command, bool quiet)
    : command_(std::move(command)),
      quiet_(quiet),
      tty_(::isatty(STDERR_FILENO) != 0),
      lastTime_(std::chrono::steady_clock::now()) {}

void ProgressLine::update(double fraction, const std::string& text) {
  if (quiet_) return;
  if (tty_) {
    std::fprintf(stderr, "\r%s: %3.0f%%  %s  ", command_.c_str(), 100.0 * fraction, text.c_str());
    shown_ = true;
    return;
  }
  const auto now = std::chrono::steady_clock::now();
  if (fraction < lastFraction_ + 0.1 && fraction < 1.0 && now - lastTime_ < std::chrono::seconds(5))
    return;
  lastFraction_ = fraction;
  lastTime_ = now;
  std::fprintf(stderr, "%s: %3.0f%%  %s\n", command_.c_str(), 100.0 * fraction, text.c_str());
}

void ProgressLine::done() {
  if (shown_) std::fprintf(stderr, "\n");
  shown_ = false;
}

}  // namespace service
