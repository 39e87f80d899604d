#include "hlod/study/BuildStudy.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hlod/metrics/SimplifiedFacing.h"
#include "hlod/metrics/SurfaceDistance.h"
#include "hlod/store/NodeStore.h"

namespace hlod::study {

namespace {

void append(Mesh& dst, const Mesh& src) {
  const auto base = std::uint32_t(dst.positions.size());
  dst.positions.insert(dst.positions.end(), src.positions.begin(), src.positions.end());
  for (std::uint32_t i : src.indices) dst.indices.push_back(base + i);
}

LevelFigures& levelOf(SimplifierFigures& f, int level) {
  while (int(f.levels.size()) <= level) {
    f.levels.emplace_back();
    f.levels.back().level = int(f.levels.size()) - 1;
  }
  return f.levels[std::size_t(level)];
}

}  // namespace

Result<BuildStudy> BuildStudy::create(const BuildStudyOptions& options) {
  if (options.simplifiers.empty()) return makeError("no simplifier to study");
  if (options.samplesPerBlock == 0) return makeError("samples per block must be at least 1");
  if (options.build.levelFactor < 2 || options.build.levelFactor > 64)
    return makeError("levelFactor must be an integer in [2, 64]");
  if (options.build.desiredTri < 1) return makeError("desiredTri must be at least 1");
  BuildStudy s;
  s.options_ = options;
  for (const std::string& name : options.simplifiers) {
    auto simplifier = makeSimplifier(name);
    if (!simplifier) return simplifier.error();
    s.simplifiers_.push_back(std::move(*simplifier));
    s.figures_.emplace_back();
    s.figures_.back().simplifier = name;
  }
  return s;
}

namespace {

// One level's figures: the surface its cut draws against the original, and the facing of its
// simplified (inner) nodes, each with the error its node records, against the original indexed
// once (checker: an Error for an original checkFacing refuses, reported only when needed).
Status measureLevel(LevelFigures& L, const Mesh& original,
                    const Result<metrics::FacingChecker>& checker, const Mesh& cut,
                    const std::vector<std::pair<Mesh, double>>& simplified, std::size_t samples,
                    const std::string& what) {
  const double diagonal = glm::length(original.bounds().size());
  for (const auto& [mesh, error] : simplified) {
    if (mesh.triangleCount() == 0) continue;
    if (!checker) return makeError(what + ": " + checker.message());
    // Standing off: farther from the original than the node says it is (and than a millionth
    // of the whole, which is no shard).
    auto facing = metrics::checkFacing(*checker, mesh, std::max(error, 1e-6 * diagonal));
    if (!facing) return makeError(what + ": " + facing.message());
    L.simplifiedTriangles += facing->triangles;
    L.flipped += facing->flipped;
    L.standingOff += facing->standingOff;
    L.maxOff = std::max(L.maxOff, facing->maxOff);
  }
  L.triangles += cut.triangleCount();
  auto distance = metrics::surfaceDistance(original, cut, samples);
  if (!distance) return makeError(what + ": " + distance.message());
  L.hausdorff = std::max(L.hausdorff, distance->hausdorff);
  if (diagonal > 0.0) L.relHausdorff = std::max(L.relHausdorff, distance->hausdorff / diagonal);
  L.sumSquares += distance->rms * distance->rms * double(distance->samples);
  L.samples += distance->samples;
  L.rms = std::sqrt(L.sumSquares / double(L.samples));
  return Ok{};
}

Mesh worldMesh(const LocalMesh& m) {
  Mesh out;
  out.positions.reserve(m.positions.size());
  for (const glm::vec3& p : m.positions) out.positions.push_back(m.centre + glm::dvec3(p));
  out.indices = m.indices;
  return out;
}

}  // namespace

Status BuildStudy::addObjectModel(const Model& model, const std::filesystem::path& scratch) {
  Mesh original;
  for (const Mesh& m : model.meshes) append(original, m);
  if (original.triangleCount() == 0) return Ok{};
  const auto checker = metrics::FacingChecker::create(original);
  const std::size_t samples =
      options_.samplesPerBlock *
      std::max<std::size_t>(
          1, original.triangleCount() / std::max<std::size_t>(1, options_.build.maxBlockTriangles));
  for (std::size_t k = 0; k < simplifiers_.size(); ++k) {
    SimplifierFigures f;
    f.simplifier = simplifiers_[k]->name();
    f.hierarchy = "objects";
    BuildOptions o = options_.build;
    o.simplifier = f.simplifier;
    o.cells = CellMode::Off;
    const std::filesystem::path dir = scratch / ("objects-" + f.simplifier + ".hlod");
    const auto t0 = std::chrono::steady_clock::now();
    {
      auto builder = HlodBuilder::create(dir, o);
      if (!builder) return builder.error();
      (*builder)->setModelFrame(upAxisOf(model), model.crs);
      const ObjectHierarchy h = buildObjectHierarchy(model, objectHierarchyOptions(o));
      if (auto st = (*builder)->addObjectHierarchy(model, h); !st) return st;
      if (auto sk = (*builder)->finish(0.0); !sk) return sk.error();
    }
    f.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    f.inputTriangles = original.triangleCount();
    auto store = NodeStore::open(dir);
    if (!store) return store.error();
    const Skeleton& s = (*store)->skeleton();
    std::uint32_t depth = 0;
    for (const NodeInfo& n : s.nodes) depth = std::max(depth, n.level);
    // Per level, the cut's nodes loaded from the store (one level in memory at a time).
    for (std::uint32_t d = 0; d <= depth; ++d) {
      LevelFigures& L = levelOf(f, int(d));
      L.blocks = 1;
      Mesh cut;
      std::vector<std::pair<Mesh, double>> simplified;
      for (std::uint32_t n = 0; n < s.nodes.size(); ++n) {
        const NodeInfo& info = s.nodes[n];
        const bool leaf = info.childCount == 0;
        if (info.level != d && !(leaf && info.level < d)) continue;
        auto mesh = (*store)->loadNode(n);
        if (!mesh) return mesh.error();
        Mesh world = worldMesh(*mesh);
        append(cut, world);
        if (info.level != d) continue;
        ++L.nodes;
        L.geometricError = std::max(L.geometricError, info.geometricError);
        if (!leaf) simplified.emplace_back(std::move(world), info.geometricError);
      }
      if (auto st = measureLevel(L, original, checker, cut, simplified, samples,
                                 "objects level " + std::to_string(d));
          !st)
        return st;
    }
    store = makeError("closed");
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    figures_.push_back(std::move(f));
  }
  return Ok{};
}

Status BuildStudy::addBlock(const Block& block) {
  const Mesh original = weldVertices(block.mesh);
  if (original.triangleCount() == 0) return Ok{};
  for (std::size_t k = 0; k < simplifiers_.size(); ++k) {
    SimplifierFigures& f = figures_[k];
    BuildOptions o = options_.build;
    o.simplifier = simplifiers_[k]->name();
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<BlockNode> nodes =
        buildBlockHierarchy(block.mesh, o, *simplifiers_[k], block.seam, block.sides);
    f.buildSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    f.inputTriangles += original.triangleCount();
    int depth = 0;
    for (const BlockNode& n : nodes) depth = std::max(depth, int(n.info.level));
    // The cut at level d: the nodes of level d and the leaves above it.
    const auto checker = metrics::FacingChecker::create(original);
    for (int d = 0; d <= depth; ++d) {
      Mesh cut;
      LevelFigures& L = levelOf(f, d);
      ++L.blocks;
      std::vector<std::pair<Mesh, double>> simplified;
      for (const BlockNode& n : nodes) {
        const int level = int(n.info.level);
        const bool leaf = n.info.childCount == 0;
        if (level == d || (leaf && level < d)) append(cut, n.mesh);
        if (level != d) continue;
        ++L.nodes;
        L.geometricError = std::max(L.geometricError, n.info.geometricError);
        if (!leaf) simplified.emplace_back(n.mesh, n.info.geometricError);
      }
      if (auto st = measureLevel(L, original, checker, cut, simplified, options_.samplesPerBlock,
                                 "block " + block.mesh.name);
          !st)
        return st;
    }
  }
  return Ok{};
}

std::string buildStudyJson(const std::vector<SimplifierFigures>& figures) {
  nlohmann::json out = {{"simplifiers", nlohmann::json::array()}};
  for (const SimplifierFigures& f : figures) {
    nlohmann::json levels = nlohmann::json::array();
    for (const LevelFigures& L : f.levels)
      levels.push_back({{"level", L.level},
                        {"blocks", L.blocks},
                        {"nodes", L.nodes},
                        {"triangles", L.triangles},
                        {"hausdorff", L.hausdorff},
                        {"rms", L.rms},
                        {"relHausdorff", L.relHausdorff},
                        {"geometricError", L.geometricError},
                        {"simplifiedTriangles", L.simplifiedTriangles},
                        {"flipped", L.flipped},
                        {"standingOff", L.standingOff},
                        {"maxOff", L.maxOff}});
    out["simplifiers"].push_back({{"simplifier", f.simplifier},
                                  {"hierarchy", f.hierarchy},
                                  {"buildSeconds", f.buildSeconds},
                                  {"inputTriangles", f.inputTriangles},
                                  {"levels", levels}});
  }
  return out.dump(1) + "\n";
}

std::string buildStudyCsv(const std::vector<SimplifierFigures>& figures) {
  std::ostringstream s;
  s << "hierarchy,simplifier,buildSeconds,level,blocks,nodes,triangles,hausdorff,rms,relHausdorff,"
       "geometricError,simplifiedTriangles,flipped,standingOff,maxOff\n";
  char line[512];
  for (const SimplifierFigures& f : figures)
    for (const LevelFigures& L : f.levels) {
      std::snprintf(line, sizeof line,
                    "%s,%s,%.3f,%d,%zu,%zu,%zu,%.6g,%.6g,%.6g,%.6g,%zu,%zu,%zu,%.6g\n",
                    f.hierarchy.c_str(), f.simplifier.c_str(), f.buildSeconds, L.level, L.blocks,
                    L.nodes, L.triangles, L.hausdorff, L.rms, L.relHausdorff, L.geometricError,
                    L.simplifiedTriangles, L.flipped, L.standingOff, L.maxOff);
      s << line;
    }
  return s.str();
}

}  // namespace hlod::study
