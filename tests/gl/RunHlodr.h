#pragma once
// Runs the `hlodr` executable as a user would, capturing its exit status and output.
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace gltest {

struct Run {
  int status = -1;
  std::string output;  // stdout and stderr together
};

// env: assignments put before the command, e.g. "HLODR_GL_BACKEND=egl".
inline Run runHlodr(const std::string& args, const std::string& env = "") {
  Run r;
  const std::string cmd = env + " " + HLODR_BINARY + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

}  // namespace gltest
