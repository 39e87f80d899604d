#pragma once
// Frustum culling that starts at the block quadtree (Parry sec. 3: "The global quadtree
// hierarchy is used to organize the blocks for fast view culling"): whole cells of blocks far
// outside the view are skipped before any of their roots is looked at.
//
// A cell is skipped only when its box lies farther outside the frustum than falloff times the
// largest box diagonal among its roots. A root's box inside the cell's is never nearer the
// frustum (Frustum::distanceOutside grows as a box shrinks), so each such root lies beyond its
// own fall-off, c_visFalloff times its diagonal: invisible, with frustumVis 0 (Lakhia's
// PriorityModel::evaluate). No front changes; only those roots' load priorities (always
// resident, never loaded) are left out.
#include <cstdint>
#include <vector>

#include "hlod/runtime/Camera.h"
#include "hlod/store/Skeleton.h"

namespace hlod {

struct QuadtreeWalk {
  std::uint32_t cellsVisited = 0;  // cells whose box was tested
  std::uint32_t cellsCulled = 0;   // of them, skipped with all below them
};

class QuadtreeCulling {
 public:
  explicit QuadtreeCulling(const Skeleton& skeleton);

  // Fills `roots` with the roots of every leaf cell reached, in ascending order (the order of
  // Skeleton::roots, which decodeSkeleton checks); without a quadtree, or with cell nodes (the
  // quadtree's blocks are then not roots; the cells cull them), with Skeleton::roots.
  // falloff: c_visFalloff (a negative or NaN one counts as 0).
  QuadtreeWalk candidateRoots(const Frustum& frustum, double falloff,
                              std::vector<std::uint32_t>& roots) const;

 private:
  const Skeleton& skeleton_;
  std::vector<double> reach_;  // per cell: the largest diagonal of its roots' boxes
};

}  // namespace hlod
