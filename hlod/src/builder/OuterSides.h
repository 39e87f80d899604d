#pragma once
// The outer sides of a cell of blocks (builder/CellNodes.h): where a cell node's outline must stay
// put when it is simplified, as a block's sides do (markOutline), because a neighbouring cell
// meets it there. Private to the builder.
#include <span>
#include <vector>

#include "hlod/builder/HlodBuilder.h"

namespace hlod {

// The sides (CutPlane) of a cell's blocks that face no other block of the cell: a block's side
// is inner when another block of the cell lies across it (its box ends on the same plane from
// the other side, overlapping along the plane, across `up`). boxes[k] and sides[k] are block k's.
std::vector<CutPlane> outerSides(std::span<const Aabb> boxes,
                                 std::span<const std::vector<CutPlane>> sides, UpAxis up);

}  // namespace hlod
