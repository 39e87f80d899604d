// The builder on the default city and on every shared mesh, per simplifier: input triangles,
// leaf triangles (and their ratio), the store's size stored and decoded (textures apart), build
// rate and peak memory. Each build is a `hlodr build` child process, so its peak RSS is its own
// (wait4), and an older hlodr can be measured side by side with --hlodr. The figures come from
// `hlodr info STORE --json`; an hlodr whose info has no texture fields prints "-" there.
//
// usage: build_bench [--hlodr PATH] [--simplifiers meshopt,openmesh] [--threads N]
//                    [--city-blocks N] [--cases city,bunny00.off,...]
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace fs = std::filesystem;

namespace {

struct Run {
  bool ok = false;
  double seconds = 0.0;
  double peakMb = 0.0;
};

// Runs argv to completion; its wall time and peak RSS.
Run runChild(const std::vector<std::string>& argv) {
  Run r;
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  int status = 0;
  struct rusage usage {};
  wait4(pid, &status, 0, &usage);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.peakMb = double(usage.ru_maxrss) / 1024.0;
  r.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  return r;
}

std::string output(const std::string& command) {
  std::string out;
  if (FILE* p = popen(command.c_str(), "r")) {
    char buf[4096];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    pclose(p);
  }
  return out;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

// A field summed over the levels and the cell nodes of `hlodr info --json`.
std::string mb(const nlohmann::json& info, const char* field) {
  double sum = 0.0;
  for (const auto& l : info["levels"]) {
    if (!l.contains(field)) return "-";
    sum += l[field].get<double>();
  }
  if (info.contains("cells")) sum += info["cells"].value(field, 0.0);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", sum / 1e6);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  std::string hlodr = HLODR_BINARY, threads;
  std::vector<std::string> simplifiers = {"meshopt", "openmesh"};
  std::vector<std::string> cases = {"city",
                                    "bunny00.off",
                                    "refined_elephant.off",
                                    "armadillo.off",
                                    "head.stl",
                                    "2CylinderEngine.glb",
                                    "peterbilt/peterbilt.obj",
                                    "rotterdam-delfshaven.cityjson.json"};
  std::string cityBlocks = "64";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string o = argv[i], v = argv[i + 1];
    if (o == "--hlodr")
      hlodr = v;
    else if (o == "--simplifiers")
      simplifiers = split(v);
    else if (o == "--threads")
      threads = v;
    else if (o == "--city-blocks")
      cityBlocks = v;
    else if (o == "--cases")
      cases = split(v);
    else {
      std::fprintf(stderr, "build_bench: unknown option %s\n", o.c_str());
      return 2;
    }
  }
  const fs::path tmp =
      fs::temp_directory_path() / ("hlodr-build-bench-" + std::to_string(getpid()));
  fs::create_directories(tmp);
  std::printf("HLOD build benchmark: %s, threads %s\n", hlodr.c_str(),
              threads.empty() ? "default" : threads.c_str());
  std::printf("%-34s %-8s %10s %10s %6s %9s %9s %9s %9s %7s %7s %8s\n", "case", "simp", "input",
              "leaves", "ratio", "stored", "of which", "decoded", "of which", "build", "Mtri/s",
              "peak");
  std::printf("%-34s %-8s %10s %10s %6s %9s %9s %9s %9s %7s %7s %8s\n", "", "", "triangles",
              "triangles", "", "MB", "tex MB", "MB", "tex MB", "s", "", "RSS MB");
  for (const std::string& c : cases) {
    fs::path input = fs::path(HLODR_SHARED_DATA) / c;
    if (c == "city") {
      input = tmp / "city";
      if (!runChild({hlodr, "city", "-o", input.string(), "--blocks", cityBlocks, "--quiet"}).ok) {
        std::printf("%-34s city generation FAILED\n", c.c_str());
        continue;
      }
    } else if (!fs::exists(input)) {
      std::printf("%-34s skipped: %s is absent\n", c.c_str(), input.c_str());
      continue;
    }
    for (const std::string& s : simplifiers) {
      const fs::path store = tmp / "store.hlod";
      std::vector<std::string> args = {
          hlodr, "build", input.string(), "-o", store.string(), "--simplifier", s, "--quiet"};
      if (!threads.empty()) args.insert(args.end(), {"--threads", threads});
      const Run r = runChild(args);
      if (!r.ok) {
        std::printf("%-34s %-8s build FAILED\n", c.c_str(), s.c_str());
        continue;
      }
      nlohmann::json info;
      try {
        info =
            nlohmann::json::parse(output("'" + hlodr + "' info '" + store.string() + "' --json"));
      } catch (const std::exception& e) {
        std::printf("%-34s %-8s info FAILED (%s)\n", c.c_str(), s.c_str(), e.what());
        continue;
      }
      const double in = info["inputTriangles"].get<double>();
      const double leaves = info["leafTriangles"].get<double>();
      std::printf("%-34s %-8s %10.0f %10.0f %6.3f %9.1f %9s %9s %9s %7.1f %7.3f %8.0f\n", c.c_str(),
                  s.c_str(), in, leaves, leaves / in, info["payloadBytes"].get<double>() / 1e6,
                  mb(info, "texturePayloadBytes").c_str(), mb(info, "memoryBytes").c_str(),
                  mb(info, "textureMemoryBytes").c_str(), r.seconds, in / r.seconds / 1e6,
                  r.peakMb);
      std::fflush(stdout);
      fs::remove_all(store);
    }
  }
  fs::remove_all(tmp);
  return 0;
}
