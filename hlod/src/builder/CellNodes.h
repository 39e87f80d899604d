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
