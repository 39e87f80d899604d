#pragma once
// Cell nodes (hlod/store/Skeleton.h): the HLOD of the block quadtree's cells, built bottom up from
// the hlod_0 nodes once every block is in the store. A cell stands for its blocks when they are
// far: without cells every visible block is drawn at least as its hlod_0, which bounds a frame
// from below by the number of blocks in view (a 100 M-triangle city's hlod_0 holds 2.3 M
// triangles). Private to the builder.
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "hlod/builder/HlodBuilder.h"

namespace hlod {

// The sides (CutPlane) of a cell's blocks that face no other block of the cell: a block's side
// is inner when another block of the cell lies across it (its box ends on the same plane from
// the other side, overlapping along the plane, across `up`). boxes[k] and sides[k] are block k's.
std::vector<CutPlane> outerSides(std::span<const Aabb> boxes,
                                 std::span<const std::vector<CutPlane>> sides, UpAxis up);

// A cell is drawn in flat colours: a texture atlas of its children would not survive the
// simplification, whose triangles join vertices of different children (and of different
// children's atlases). mergeCellChildren gives the children as one world-space mesh whose
// texture coordinates hold, in x, an index into `colours`: each vertex's colour, the mean of its
// triangles' colours over their texture footprints (weighted by area) times its base colour.
// Vertices of one position and one colour weld; the simplifier keeps copies of input vertices,
// so the index survives it.
struct ColouredMesh {
  Mesh mesh;
  std::vector<glm::vec4> colours;
};
ColouredMesh mergeCellChildren(std::span<const LocalMesh> children);

// The simplified mesh in flat colours: each triangle the mean of its corners' colours, from a
// palette texture of one texel per distinct colour, all three corners of a triangle at its
// texel's centre (equal coordinates: the sampler stays at the base level, so no mipmap blends
// neighbouring colours), and flat shaded (three vertices per triangle, its face's normal).
Mesh flatColoured(const Mesh& simplified, std::span<const glm::vec4> colours);

// Keeps one of triangles with the same three vertices in the same turn: children that repeat
// their triangles (a pile of copies of one quad, which nothing can simplify) would otherwise hand
// the shape guard a pile whose every triangle is every query's nearest.
void dropRepeatedTriangles(Mesh& mesh);

// Splits each open-border edge lying on one of the planes at the border positions of the other
// children strictly inside it: two blocks' grounds meet at a street's middle with the same
// corners, but each dropped other straight-run vertices (kVertexOnOutline), and the T-junctions
// left would keep the street an open border, which the simplification then opens into a gap.
// Within `tolerance` of the segment, and the planes' sides run along the axis across `up`.
void stitchBorders(Mesh& mesh, std::span<const CutPlane> planes, UpAxis up, double tolerance);

// Below this fraction of its horizontal size under its lowest point, a cell's underlay.
constexpr double kUnderlayDepth = 0.01;
// Appends the underlay of a cell of `box` to its simplified mesh (texture coordinates: colour
// indices, as mergeCellChildren's): a quad facing up over the box's footprint, kUnderlayDepth
// of its larger horizontal side below its bottom, in the area-weighted colour of `input`'s
// triangles facing up within a metre of the bottom (appended to colours). Nothing without them.
void addUnderlay(Mesh& mesh, const Mesh& input, std::vector<glm::vec4>& colours, const Aabb& box,
                 UpAxis up);

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

// What the cell pass needs from the builder: the skeleton of the committed blocks (each block's
// hlod_0 node in the quadtree), the writer holding their payloads, and per block (NodeInfo::block)
// its sides and seam as addBlock had them.
struct CellPass {
  Skeleton& skeleton;
  NodeStoreWriter& writer;
  const Simplifier& simplifier;
  const BuildOptions& options;
  std::span<const std::vector<CutPlane>> sides;
  std::span<const std::vector<glm::dvec3>> seams;
  std::function<void(std::size_t done, std::size_t total)>
      progress;  // quadtree cells; may be empty
};

// Adds a cell node for each quadtree cell with at least two nodes below it (a cell with one
// stands for that one), made from its children's payloads:
// - positions put back on the blocks' sides and seams (snapOnto), and the children stitched
//   along the sides between them (stitchBorders), so that they weld into one surface there;
// - simplified (Simplifier::simplifyUnion) to its children's triangles over levelFactor (as a
//   block's levels), at least desiredTri, with seam positions shared with a block outside the
//   cell locked and the outline kept on its outer sides (markOutline), as a block's nodes are;
// - when its blocks have sides (a city's ground reaching the middles of its streets), its
//   buildings as boxes (takeBuildings), the largest within half the target, the rest dropped
//   (their height counts in its geometric error), the ground and the buildings that are no box
//   simplified apart (so that no triangle joins a roof to the street) to the rest, shared as
//   their triangles, and
// - an underlay when its blocks have sides (a city's ground reaching the middles of its
//   streets): its footprint at the colour of its lowest ground, kUnderlayDepth of its size below
//   it, which shows where the simplification opened a street (no sky through the ground);
// - flat colours, no progression; its geometric error is its children's largest plus its own.
// Then orders the nodes breadth-first from the top cell, the one root (parents before children,
// siblings contiguous), and renumbers the quadtree's blocks. Returns how many cells it made.
Result<std::uint32_t> addCellNodes(CellPass& pass);

}  // namespace hlod
