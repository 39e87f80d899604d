// Build throughput (input triangles/s) and peak memory (ru_maxrss) of the HLOD builder on the
// procedural city, per simplifier, and the peak memory of a city ten times larger: the builder
// streams blocks, so memory should stay bounded by the largest block, not grow with the city.
//
// Each case runs in a child process, so that its ru_maxrss is its own. Blocks come from
// hlod::generateBlock one at a time (the city generator's own stream), straight into the
// streaming HlodBuilder; the store is written to a temporary folder and removed.
//
// usage: build_bench [--blocks N] [--big-blocks N] [--desired-tri N]
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "hlod/builder/HlodBuilder.h"
#include "hlod/city/City.h"

namespace {

struct CaseResult {
  double seconds = 0;
  unsigned long long triangles = 0;
  unsigned long long nodes = 0;
  unsigned long long payloadBytes = 0;
  int ok = 0;
};

CaseResult runCase(int blocks, const std::string& simplifier, std::uint32_t desiredTri) {
  CaseResult r;
  const auto dir = std::filesystem::temp_directory_path() /
                   ("hlodr-build-bench-" + std::to_string(::getpid()) + ".hlod");
  hlod::BuildOptions o;
  o.simplifier = simplifier;
  o.desiredTri = desiredTri;
  auto builder = hlod::HlodBuilder::create(dir, o);
  if (!builder) return r;
  hlod::CityOptions city;
  city.blocks = blocks;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < blocks; ++i) {
    const hlod::Mesh block = hlod::generateBlock(city, i);
    r.triangles += block.triangleCount();
    if (!(*builder)->addBlock(block)) return r;
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  auto skel = (*builder)->finish(secs);
  r.seconds = secs;
  if (skel) {
    r.nodes = skel->nodes.size();
    std::error_code ec;
    r.payloadBytes = std::filesystem::file_size(dir / "payload.bin", ec);
    r.ok = 1;
  }
  std::filesystem::remove_all(dir);
  return r;
}

// Generation alone, to subtract from the build figures.
CaseResult runGenerateOnly(int blocks) {
  CaseResult r;
  hlod::CityOptions city;
  city.blocks = blocks;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < blocks; ++i) r.triangles += hlod::generateBlock(city, i).triangleCount();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.ok = 1;
  return r;
}

void report(const char* name, int blocks, const std::string& simplifier, std::uint32_t desiredTri,
            bool generateOnly) {
  int fds[2];
  if (pipe(fds) != 0) return;
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    const CaseResult r =
        generateOnly ? runGenerateOnly(blocks) : runCase(blocks, simplifier, desiredTri);
    if (write(fds[1], &r, sizeof r) != sizeof r) _exit(1);
    _exit(0);
  }
  close(fds[1]);
  CaseResult r;
  const bool got = read(fds[0], &r, sizeof r) == sizeof r;
  close(fds[0]);
  int status = 0;
  struct rusage usage {};
  wait4(pid, &status, 0, &usage);
  if (!got || !r.ok) {
    std::printf("%-26s FAILED\n", name);
    return;
  }
  std::printf(
      "%-26s %5d blocks %11llu tri %7.1f s %8.3f Mtri/s %7llu nodes %9.1f MB payload "
      "%8.1f MB peak RSS\n",
      name, blocks, r.triangles, r.seconds, r.triangles / r.seconds / 1e6, r.nodes,
      r.payloadBytes / 1e6, usage.ru_maxrss / 1024.0);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  int blocks = hlod::kDefaultCityBlocks, bigBlocks = 10 * hlod::kDefaultCityBlocks;
  std::uint32_t desiredTri = hlod::kDefaultDesiredTri;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--blocks")) blocks = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--big-blocks")) bigBlocks = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--desired-tri")) desiredTri = std::uint32_t(std::atoi(argv[i + 1]));
  }
  std::printf(
      "HLOD build benchmark: default city = %d blocks, large city = %d blocks, "
      "desiredTri %u, levelFactor 3\n",
      blocks, bigBlocks, desiredTri);
  report("generate only", blocks, "", desiredTri, true);
  report("build city, meshopt", blocks, "meshopt", desiredTri, false);
  report("build city, openmesh", blocks, "openmesh", desiredTri, false);
  if (bigBlocks > 0) report("build 10x city, meshopt", bigBlocks, "meshopt", desiredTri, false);
  return 0;
}
