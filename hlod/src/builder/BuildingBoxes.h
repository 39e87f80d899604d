#pragma once
// Buildings as boxes (builder/CellNodes.h): far away a city's buildings are drawn as the block
// models of a city's LoD1 (CityGML), a box per building at its mean roof height in its mean wall
// and roof colours, ten triangles each. Private to the builder.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"
#include "hlod/UpAxis.h"

namespace hlod {

// A building as a box (a city's LoD1): its footprint a rectangle along `axis` (a unit vector in
// the plane across `up`, the horizontal axes in the order (up+1, up+2)), lo..hi in that frame,
// from bottom to top along up, its walls and its roof in their mean colours.
struct BuildingBox {
  glm::dvec2 axis{1.0, 0.0};
  glm::dvec2 lo{0.0}, hi{0.0};
  double bottom = 0.0, top = 0.0;
  glm::vec4 side{1.0f}, roof{1.0f};
  double silhouette() const { return (top - bottom) * glm::length(hi - lo); }
};
// A part at least 1/kGroundAspect as tall as it is wide is a building; flatter ones are ground.
constexpr double kGroundAspect = 4.0;
constexpr std::size_t kBoxTriangles = 10;  // its roof and four walls
// A part whose roofs (triangles facing up) cover less of its box's footprint is no box (buildings
// joined around a courtyard): it stays in the mesh.
constexpr double kBoxFill = 0.5;
// A part over a building's footprint (this much of its own), its bottom this much of the
// building's height above the building's, belongs to it: its roof, or what stands on the roof.
constexpr double kOnFootprint = 0.5;
constexpr double kRoofLift = 0.1;

// Takes the buildings out of a mesh of mergeCellChildren's (texture coordinates: colour
// indices): each connected part (by position) that is not ground and fills its box (kBoxFill)
// becomes a box around it, as high as the volume under its roofs over their footprint, turned
// to the main direction of its walls' edges, coloured by the area-weighted mean of its triangles
// facing up (the roof) and of the others (the walls). Leaves the ground's triangles in the mesh;
// the boxes come tallest and widest (BuildingBox::silhouette) first.
// others (when given): the triangles of the parts that are buildings but no box, taken out too.
std::vector<BuildingBox> takeBuildings(Mesh& mesh, std::span<const glm::vec4> colours, UpAxis up,
                                       std::vector<std::uint32_t>* others = nullptr);
// Appends a box's roof and walls (no floor), facing out, with their colours' indices.
void appendBox(Mesh& mesh, const BuildingBox& box, std::vector<glm::vec4>& colours, UpAxis up);

}  // namespace hlod
