// Buildings grouped into grid blocks (hlod/builder/CityBlocks.h).
#include "hlod/builder/CityBlocks.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>
#include <unordered_map>

#include "builder/SimplifierImpl.h"
#include "builder/SlabPartition.h"

namespace hlod {

namespace {

constexpr std::uint32_t kNoObject = 0xffffffffu;

// The grid cell of a coordinate, clamped far beyond any model (coordinates reach 1.7e38).
std::int64_t cellOf(double v, double blockSize) {
  return std::int64_t(std::clamp(std::floor(v / blockSize), -4e18, 4e18));
}

}  // namespace

std::vector<BuildingBlock> groupBuildingsIntoBlocks(const Model& model, double blockSize) {
  assert(blockSize > 0.0 && std::isfinite(blockSize));
  std::vector<BuildingBlock> out;
  if (model.objectRuns.empty()) {
    BuildingBlock all;
    all.model = model;
    all.buildings = model.cityObjects;
    out.push_back(std::move(all));
    return out;
  }
  // Each triangle's object, and each object's footprint box (x, y).
  std::vector<std::vector<std::uint32_t>> objectOf(model.meshes.size());
  for (std::size_t m = 0; m < model.meshes.size(); ++m)
    objectOf[m].assign(model.meshes[m].triangleCount(), kNoObject);
  std::uint32_t objects = 0;
  for (const ObjectRun& r : model.objectRuns) objects = std::max(objects, r.object + 1);
  std::vector<Aabb> footprint(objects);
  for (const ObjectRun& r : model.objectRuns) {
    const Mesh& mesh = model.meshes[r.mesh];
    for (std::uint32_t t = r.firstTriangle; t < r.firstTriangle + r.triangleCount; ++t) {
      objectOf[r.mesh][t] = r.object;
      for (int k = 0; k < 3; ++k)
        footprint[r.object].extend(mesh.positions[mesh.indices[3 * t + k]]);
    }
  }
  // Blocks by cell, rows first; per block and mesh the triangles it takes.
  std::map<std::pair<std::int64_t, std::int64_t>, std::size_t> blockOfCell;  // (y, x) -> block
  std::vector<std::vector<std::vector<std::uint32_t>>> triangles;            // block, mesh
  std::vector<std::size_t> blockOfObject(objects, SIZE_MAX);
  const auto blockAt = [&](const glm::dvec3& centre) {
    const std::int64_t cx = cellOf(centre.x, blockSize), cy = cellOf(centre.y, blockSize);
    auto [it, fresh] = blockOfCell.try_emplace({cy, cx}, out.size());
    if (fresh) {
      out.emplace_back().cell = {cx, cy};
      triangles.emplace_back(model.meshes.size());
    }
    return it->second;
  };
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    for (std::uint32_t t = 0; t < objectOf[m].size(); ++t) {
      const std::uint32_t o = objectOf[m][t];
      std::size_t b;
      if (o == kNoObject) {
        b = blockAt(centroid(model.meshes[m], t));
      } else {
        if (blockOfObject[o] == SIZE_MAX) {
          blockOfObject[o] = blockAt(footprint[o].centre());
          ++out[blockOfObject[o]].buildings;
        }
        b = blockOfObject[o];
      }
      triangles[b][m].push_back(t);
    }
  }
  // Which positions more than one block has.
  std::unordered_map<glm::dvec3, std::size_t, PositionHash> firstBlock;
  std::unordered_map<glm::dvec3, std::uint8_t, PositionHash> sharedAt;
  for (std::size_t b = 0; b < out.size(); ++b) {
    for (std::size_t m = 0; m < model.meshes.size(); ++m) {
      const Mesh& mesh = model.meshes[m];
      for (std::uint32_t t : triangles[b][m])
        for (int k = 0; k < 3; ++k) {
          const glm::dvec3 p = mesh.positions[mesh.indices[3 * t + k]] + glm::dvec3(0.0);
          auto [it, fresh] = firstBlock.try_emplace(p, b);
          if (!fresh && it->second != b) sharedAt[p] = 1;
        }
    }
  }
  for (std::size_t b = 0; b < out.size(); ++b) {
    BuildingBlock& block = out[b];
    block.model.format = model.format;
    block.model.crs = model.crs;
    block.model.zUp = model.zUp;
    for (std::size_t m = 0; m < model.meshes.size(); ++m) {
      if (triangles[b][m].empty()) continue;
      block.model.meshes.push_back(subMesh(model.meshes[m], triangles[b][m]));
      triangles[b][m] = {};
      for (const glm::dvec3& p : block.model.meshes.back().positions)
        if (sharedAt.count(p + glm::dvec3(0.0))) block.shared.push_back(p);
    }
    std::sort(block.shared.begin(), block.shared.end(),
              [](const glm::dvec3& p, const glm::dvec3& q) {
                return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
              });
    block.shared.erase(std::unique(block.shared.begin(), block.shared.end()), block.shared.end());
    block.model.cityObjects = block.buildings;
  }
  // Rows south to north, then west to east: the map's order.
  std::vector<BuildingBlock> sorted;
  sorted.reserve(out.size());
  for (const auto& [cell, b] : blockOfCell) sorted.push_back(std::move(out[b]));
  return sorted;
}

}  // namespace hlod
