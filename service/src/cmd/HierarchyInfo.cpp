// `hlodr info`: the hierarchy criteria of Manocha sec. 2.1.1 (cmd/HierarchyInfo.h).
#include "cmd/HierarchyInfo.h"

#include <cstdio>
#include <string>
#include <vector>

#include "hlod/builder/HierarchyCriteria.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/builder/ObjectHierarchy.h"

namespace service::cmd {

namespace {

nlohmann::json toJson(const hlod::Spread3& s) {
  return {{"min", s.min}, {"median", s.median}, {"max", s.max}};
}

nlohmann::json toJson(const hlod::HierarchyFigures& f, bool objects) {
  nlohmann::json j = {{"nodes", f.nodes},
                      {"leaves", f.leaves},
                      {"roots", f.roots},
                      {"innerFill", f.innerFill},
                      {"depth", f.depth},
                      {"minLeafDepth", f.minLeafDepth},
                      {"meanLeafDepth", f.meanLeafDepth},
                      {"balance", f.balance},
                      {"siblingOverlap", f.siblingOverlap},
                      {"overlappingPairs", f.overlappingPairs},
                      {"leafTriangles", toJson(f.leafTriangles)},
                      {"leafDiagonal", toJson(f.leafDiagonal)}};
  if (objects) {
    j["leavesPerObject"] = f.leavesPerObject;
    j["objectsCut"] = f.objectsCut;
  }
  return j;
}

// Rows of the table, one column per hierarchy.
void printTable(const std::vector<std::string>& names,
                const std::vector<hlod::HierarchyFigures>& figures, bool objects) {
  const auto row = [&](const char* label, auto cell) {
    std::printf("  %-30s", label);
    for (const hlod::HierarchyFigures& f : figures) std::printf("  %-22s", cell(f).c_str());
    std::printf("\n");
  };
  const auto fmt = [](const char* format, auto... v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v...);
    return std::string(buf);
  };
  std::printf("\nhierarchy (Manocha sec. 2.1.1)  ");
  for (const std::string& n : names) std::printf("  %-22s", n.c_str());
  std::printf("\n");
  row("nodes, leaves, roots",
      [&](const auto& f) { return fmt("%zu, %zu, %zu", f.nodes, f.leaves, f.roots); });
  row("1 localisation: inner fill", [&](const auto& f) { return fmt("%.3f", f.innerFill); });
  if (objects) {
    row("  leaves per object", [&](const auto& f) { return fmt("%.3f", f.leavesPerObject); });
    row("  objects cut", [&](const auto& f) { return fmt("%.1f%%", 100.0 * f.objectsCut); });
  }
  row("2 depth: max, mean, min leaf",
      [&](const auto& f) { return fmt("%u, %.2f, %u", f.depth, f.meanLeafDepth, f.minLeafDepth); });
  row("  balance (min/max leaf depth)", [&](const auto& f) { return fmt("%.3f", f.balance); });
  row("3 sibling overlap: volume", [&](const auto& f) { return fmt("%.4f", f.siblingOverlap); });
  row("  pairs overlapping",
      [&](const auto& f) { return fmt("%.1f%%", 100.0 * f.overlappingPairs); });
  row("4 leaf triangles: min/med/max", [&](const auto& f) {
    return fmt("%.0f/%.0f/%.0f", f.leafTriangles.min, f.leafTriangles.median, f.leafTriangles.max);
  });
  row("  leaf diagonal/scene: med/max",
      [&](const auto& f) { return fmt("%.4f/%.4f", f.leafDiagonal.median, f.leafDiagonal.max); });
}

}  // namespace

nlohmann::json modelHierarchyInfo(const hlod::Model& model, bool print) {
  const hlod::BuildOptions options;  // hlodr build's defaults
  const hlod::ObjectHierarchy h =
      hlod::buildObjectHierarchy(model, hlod::objectHierarchyOptions(options));
  const hlod::HierarchyShape objects = hlod::shapeOf(h),
                             planes = hlod::planeCutShape(model, options);
  const double pad = hlod::defaultPad(objects);
  const hlod::HierarchyFigures fo = hlod::measureHierarchy(objects, pad),
                               fp = hlod::measureHierarchy(planes, pad);
  const hlod::HierarchyMode pick = hlod::resolveHierarchy(hlod::HierarchyMode::Auto, model);
  nlohmann::json j = {{"objects", toJson(fo, true)},
                      {"planes", toJson(fp, true)},
                      {"auto", pick == hlod::HierarchyMode::Objects ? "objects" : "planes"},
                      {"stages",
                       {{"inputObjects", h.inputObjects},
                        {"afterPartition", h.afterPartition},
                        {"clusters", h.clusters},
                        {"redefinedObjects", h.afterRepartition},
                        {"maxTriangles", hlod::objectHierarchyOptions(options).maxTriangles},
                        {"maxExtent", h.maxExtent},
                        {"k", h.k}}},
                      {"pad", pad}};
  if (!print) return j;
  printTable({"objects", "planes"}, {fo, fp}, true);
  std::printf(
      "  objects: %zu in the input, %zu after partitioning (stage 1), %zu clusters (stage 2),\n"
      "  %zu redefined objects (stage 3; at most %llu triangles and %.3g long, FH k %.3g)\n"
      "  hlodr build picks %s for this model (--hierarchy auto)\n",
      h.inputObjects, h.afterPartition, h.clusters, h.afterRepartition,
      (unsigned long long)hlod::objectHierarchyOptions(options).maxTriangles, h.maxExtent, h.k,
      pick == hlod::HierarchyMode::Objects ? "objects" : "planes");
  return j;
}

nlohmann::json storeHierarchyInfo(const hlod::Skeleton& skeleton, bool print) {
  hlod::HierarchyShape shape;
  for (const hlod::NodeInfo& n : skeleton.nodes)
    shape.nodes.push_back({n.bounds, n.parent, n.firstChild, n.childCount, n.numTri});
  const hlod::HierarchyFigures f = hlod::measureHierarchy(shape, hlod::defaultPad(shape));
  if (print) printTable({"this store"}, {f}, false);
  return toJson(f, false);
}

}  // namespace service::cmd
