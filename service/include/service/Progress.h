#pragma once
// A progress line on stderr for long commands: rewritten in place on a terminal; on a pipe or a
// log file (CI, the server's log) a plain line every 10% or every 5 seconds, so that progress
// shows wherever stderr goes.
#include <chrono>
#include <string>

namespace service {

class ProgressLine {
 public:
  ProgressLine(std::string command, bool quiet);
  // fraction in [0, 1]; text: what to show after the command's name.
  void update(double fraction, const std::string& text);
  void done();  // ends a terminal line

 private:
  std::string command_;
  bool quiet_, tty_;
  bool shown_ = false;
  double lastFraction_ = -1.0;
  std::chrono::steady_clock::time_point lastTime_;
};

}  // namespace service
