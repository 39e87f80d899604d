// `hlodr info`: what a node store holds, per level.
#include <cstdio>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "cmd/Commands.h"
#include "hlod/NodeStore.h"
#include "service/Args.h"

namespace service::cmd {

const char* const kInfoUsage =
    "usage: hlodr info STORE [--json]\n"
    "\n"
    "Prints a node store's build parameters, block count, depth, payload bytes, and nodes and\n"
    "triangles per level. Checks the skeleton (checksum, tree structure) on the way.\n"
    "\n"
    "options:\n"
    "  --json   machine-readable output\n";

namespace {

// The simplifier name is bytes from the file: escape what is not printable ASCII, so that
// terminal escape codes do not reach the terminal and the JSON stays valid UTF-8.
std::string printable(const std::string& name) {
  std::string out;
  for (const unsigned char c : name) {
    if (c >= 0x20 && c < 0x7f && c != '\\') {
      out += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
  }
  return out;
}

}  // namespace

int runInfo(const Argv& argv) {
  auto args = Args::parse(argv, {"json"}, {});
  if (!args) {
    std::fprintf(stderr, "hlodr info: %s\n%s", args.message().c_str(), kInfoUsage);
    return 2;
  }
  if (args->positionals().size() != 1) {
    std::fprintf(stderr, "hlodr info: give exactly one store\n%s", kInfoUsage);
    return 2;
  }
  auto store = hlod::NodeStore::open(args->positionals()[0]);
  if (!store) {
    std::fprintf(stderr, "hlodr info: %s\n", store.message().c_str());
    return 1;
  }
  const hlod::Skeleton& s = (*store)->skeleton();
  const hlod::StoreFacts& f = (*store)->facts();
  struct Level {
    std::size_t nodes = 0, leaves = 0;
    std::uint64_t triangles = 0, payloadBytes = 0, memoryBytes = 0;
  };
  std::map<std::uint32_t, Level> levels;
  std::uint64_t leafTriangles = 0;
  for (std::uint32_t i = 0; i < s.nodes.size(); ++i) {
    const auto& n = s.nodes[i];
    auto& l = levels[n.level];
    ++l.nodes;
    l.triangles += n.numTri;
    l.payloadBytes += n.payloadSize;
    l.memoryBytes += n.memoryBytes;
    if (s.isLeaf(i)) {
      ++l.leaves;
      leafTriangles += n.numTri;
    }
  }
  const std::size_t depth = levels.size();
  if (args->has("json")) {
    nlohmann::json j;
    j["store"] = args->positionals()[0];
    j["formatVersion"] = hlod::kSkeletonFormatVersion;
    j["params"] = {{"levelFactor", s.params.levelFactor},
                   {"desiredTri", s.params.desiredTri},
                   {"cTex", s.params.cTex},
                   {"simplifier", printable(s.params.simplifier)}};
    j["nodes"] = s.nodes.size();
    j["blocks"] = f.blockCount;
    j["depth"] = depth;
    j["inputTriangles"] = f.inputTriangles;
    j["leafTriangles"] = leafTriangles;
    j["payloadBytes"] = f.payloadBytes;
    j["buildSeconds"] = f.buildSeconds;
    j["levels"] = nlohmann::json::array();
    for (const auto& [d, l] : levels)
      j["levels"].push_back({{"level", d},
                             {"nodes", l.nodes},
                             {"leaves", l.leaves},
                             {"triangles", l.triangles},
                             {"payloadBytes", l.payloadBytes},
                             {"memoryBytes", l.memoryBytes}});
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("store         %s\n", args->positionals()[0].c_str());
  std::printf("built with    levelFactor %g, desiredTri %u, c_tex %.3f, simplifier %s (%.1f s)\n",
              s.params.levelFactor, s.params.desiredTri, s.params.cTex,
              printable(s.params.simplifier).c_str(), f.buildSeconds);
  std::printf("blocks        %u\n", f.blockCount);
  std::printf("nodes         %zu\n", s.nodes.size());
  std::printf("depth         %zu\n", depth);
  std::printf("triangles     %llu input, %llu at the leaves\n",
              (unsigned long long)f.inputTriangles, (unsigned long long)leafTriangles);
  std::uint64_t memory = 0;
  for (const auto& [d, l] : levels) memory += l.memoryBytes;
  std::printf("payload       %.2f MB stored (deflated), %.2f MB decoded\n",
              double(f.payloadBytes) / 1e6, double(memory) / 1e6);
  std::printf("\n  level     nodes    leaves     triangles   stored MB  decoded MB\n");
  for (const auto& [d, l] : levels)
    std::printf("  %5u  %8zu  %8zu  %12llu  %10.2f  %10.2f\n", d, l.nodes, l.leaves,
                (unsigned long long)l.triangles, double(l.payloadBytes) / 1e6,
                double(l.memoryBytes) / 1e6);
  return 0;
}

}  // namespace service::cmd
