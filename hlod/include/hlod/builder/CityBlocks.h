#pragma once
// Buildings grouped into city blocks, the unit of the global quadtree (Parry et al. sec. 3: "The
// data object that we store in the global hierarchy is a city block"). A CityJSON model has no
// blocks of its own, so they are made: a square grid of side blockSize over the model's
// horizontal coordinates (x, y; cells at whole multiples of blockSize from the origin of the
// model's frame), and each building (city object) goes whole into the cell its footprint centre
// lies in: the centre of its triangles' x-y box. A building is never split across blocks; a
// block may reach beyond its cell by its buildings' overhang.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"

namespace hlod {

// Metres: a city block in most cities is 60-200 m a side.
inline constexpr double kDefaultBlockSize = 100.0;

struct BuildingBlock {
  glm::i64vec2 cell{0};  // floor(footprint centre / blockSize), x then y
  Model model;           // its buildings: per source mesh (colour) with triangles here, one mesh
  std::size_t buildings = 0;
  // Positions this block shares with other blocks (walls of neighbouring buildings on either
  // side of a cell border): locked while simplifying, so that blocks meet without cracks.
  std::vector<glm::dvec3> shared;
};

// The blocks of a model's buildings, ordered by cell (rows south to north, then west to east).
// A model without city objects (Model::objectRuns empty: a mesh file) is one block holding all
// of it; triangles outside every run (none in CityJSON) are placed by their own centroid.
// blockSize must be positive and finite.
std::vector<BuildingBlock> groupBuildingsIntoBlocks(const Model& model, double blockSize);

}  // namespace hlod
