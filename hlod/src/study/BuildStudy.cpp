#include "hlod/study/BuildStudy.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hlod/metrics/SimplifiedFacing.h"
#include "hlod/metrics/SurfaceDistance.h"

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

Status BuildStudy::addBlock(const Block& block) {
  const Mesh original = weldVertices(block.mesh);
  if (original.triangleCount() == 0) return Ok{};
  const double diagonal = glm::length(original.bounds().size());
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
    for (int d = 0; d <= depth; ++d) {
      Mesh cut;
      LevelFigures& L = levelOf(f, d);
      ++L.blocks;
      for (const BlockNode& n : nodes) {
        const int level = int(n.info.level);
        const bool leaf = n.info.childCount == 0;
        if (level == d || (leaf && level < d)) append(cut, n.mesh);
        if (level != d) continue;
        ++L.nodes;
        L.geometricError = std::max(L.geometricError, n.info.geometricError);
        if (leaf || n.mesh.triangleCount() == 0) continue;
        // Standing off: farther from the original than the node says it is (and than a
        // millionth of the block, which is no shard).
        const double offLimit = std::max(n.info.geometricError, 1e-6 * diagonal);
        auto facing = metrics::checkFacing(original, n.mesh, offLimit);
        if (!facing) return makeError("block " + block.mesh.name + ": " + facing.message());
        L.simplifiedTriangles += facing->triangles;
        L.flipped += facing->flipped;
        L.standingOff += facing->standingOff;
        L.maxOff = std::max(L.maxOff, facing->maxOff);
      }
      L.triangles += cut.triangleCount();
      auto distance = metrics::surfaceDistance(original, cut, options_.samplesPerBlock);
      if (!distance) return makeError("block " + block.mesh.name + ": " + distance.message());
      L.hausdorff = std::max(L.hausdorff, distance->hausdorff);
      if (diagonal > 0.0) L.relHausdorff = std::max(L.relHausdorff, distance->hausdorff / diagonal);
      L.sumSquares += distance->rms * distance->rms * double(distance->samples);
      L.samples += distance->samples;
      L.rms = std::sqrt(L.sumSquares / double(L.samples));
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
                                  {"buildSeconds", f.buildSeconds},
                                  {"inputTriangles", f.inputTriangles},
                                  {"levels", levels}});
  }
  return out.dump(1) + "\n";
}

std::string buildStudyCsv(const std::vector<SimplifierFigures>& figures) {
  std::ostringstream s;
  s << "simplifier,buildSeconds,level,blocks,nodes,triangles,hausdorff,rms,relHausdorff,"
       "geometricError,simplifiedTriangles,flipped,standingOff,maxOff\n";
  char line[512];
  for (const SimplifierFigures& f : figures)
    for (const LevelFigures& L : f.levels) {
      std::snprintf(line, sizeof line,
                    "%s,%.3f,%d,%zu,%zu,%zu,%.6g,%.6g,%.6g,%.6g,%zu,%zu,%zu,%.6g\n",
                    f.simplifier.c_str(), f.buildSeconds, L.level, L.blocks, L.nodes, L.triangles,
                    L.hausdorff, L.rms, L.relHausdorff, L.geometricError, L.simplifiedTriangles,
                    L.flipped, L.standingOff, L.maxOff);
      s << line;
    }
  return s.str();
}

}  // namespace hlod::study
