// `hlodr info`: the view-dependent section's cluster hierarchy (cmd/VdrInfo.h).
#include "cmd/VdrInfo.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <vector>

namespace service::cmd {

namespace {

// Median, p90 and max of a list (nearest rank; zeros when empty).
struct Spread {
  double median = 0.0, p90 = 0.0, max = 0.0;
};

Spread spreadOf(std::vector<double> v) {
  Spread s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) { return v[std::size_t(q * double(v.size() - 1) + 0.5)]; };
  s.median = at(0.5);
  s.p90 = at(0.9);
  s.max = v.back();
  return s;
}

nlohmann::json toJson(const Spread& s) {
  return {{"median", s.median}, {"p90", s.p90}, {"max", s.max}};
}

struct Figures {
  std::vector<double> ratio, range, vertices;
};

}  // namespace

hlod::Result<nlohmann::json> vdrInfo(const hlod::NodeStore& store, bool print) {
  const auto& entries = store.vdrEntries();
  if (entries.empty()) return nlohmann::json(nullptr);
  Figures all;
  std::map<std::uint32_t, Figures> byDepth;
  std::uint64_t faces = 0, vertices = 0;
  nlohmann::json objects = nlohmann::json::array();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    auto object = store.loadVdrObject(i);
    if (!object)
      return hlod::makeError("vdr.bin object " + std::to_string(i) + ": " + object.message());
    const hlod::vdr::ClusterHierarchy& h = object->clusters;
    faces += entries[i].faces;
    vertices += entries[i].vertices;
    nlohmann::json clusters = nlohmann::json::array();
    for (std::uint32_t c = 0; c < h.clusters.size(); ++c) {
      const hlod::vdr::Cluster& k = h.clusters[c];
      const double ratio = h.errorRatio(c), range = h.errorRange(c);
      for (Figures* f : {&all, &byDepth[k.depth]}) {
        f->ratio.push_back(ratio);
        f->range.push_back(range);
        f->vertices.push_back(k.vertexCount);
      }
      clusters.push_back({{"depth", k.depth},
                          {"vertices", k.vertexCount},
                          {"errorRatio", ratio},
                          {"errorRange", range}});
    }
    objects.push_back({{"rootNode", entries[i].rootNode},
                       {"faces", entries[i].faces},
                       {"vertices", entries[i].vertices},
                       {"errorFloor", h.errorFloor},
                       {"clusters", std::move(clusters)}});
  }
  nlohmann::json j;
  j["objects"] = entries.size();
  j["faces"] = faces;
  j["vertices"] = vertices;
  j["clusters"] = all.ratio.size();
  j["clusterDepth"] = byDepth.empty() ? 0u : byDepth.rbegin()->first;
  j["errorRatio"] = toJson(spreadOf(all.ratio));
  j["errorRange"] = toJson(spreadOf(all.range));
  j["verticesPerCluster"] = toJson(spreadOf(all.vertices));
  j["perObject"] = std::move(objects);
  if (print) {
    std::printf(
        "\nview-dependent section (vdr.bin; Manocha sec. 3.1): %zu objects, %llu faces, %llu "
        "vertices in their hierarchies, %zu clusters\n",
        entries.size(), (unsigned long long)faces, (unsigned long long)vertices, all.ratio.size());
    std::printf(
        "error ratio: max / min error of a cluster's vertices; error range: max - min (model "
        "units); Yoon et al. 2003\n");
    std::printf("  %5s  %8s  %27s  %30s  %21s\n", "depth", "clusters",
                "error ratio: median p90 max", "error range: median p90 max",
                "vertices: median max");
    const auto row = [](const std::string& name, const Figures& f) {
      const Spread r = spreadOf(f.ratio), e = spreadOf(f.range), v = spreadOf(f.vertices);
      std::printf("  %5s  %8zu  %9.2f %8.2f %8.2f  %10.4g %9.4g %9.4g  %10.0f %10.0f\n",
                  name.c_str(), f.ratio.size(), r.median, r.p90, r.max, e.median, e.p90, e.max,
                  v.median, v.max);
    };
    for (const auto& [d, f] : byDepth) row(std::to_string(d), f);
    row("all", all);
  }
  return j;
}

}  // namespace service::cmd
