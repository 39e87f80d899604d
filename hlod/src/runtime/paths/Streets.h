#pragma once
// The streets of a city model, as the street generators (walk-fly, drive) find them: the gaps
// between the blocks' hlod_0 boxes along X and along Y, in a z-up city in metres. Private to the
// camera path generators.
#include <vector>

#include "hlod/Result.h"
#include "hlod/store/Skeleton.h"

namespace hlod {

constexpr double kMinStreet = 3.0;  // metres: narrower gaps are not streets

// Street centres along one axis: gaps between the merged [lo, hi] intervals of the block boxes,
// and lines where one block's box ends exactly where another's begins (blocks whose ground
// reaches the middle of the street, as the procedural city's do, meet there).
std::vector<double> streetsAlong(const Skeleton& sk, int axis, double minGap);

// The box of the blocks (their hlod_0 nodes): the city a street generator walks through. A cell
// node's box also holds its underlay, a share of the cell's size below the ground (CellNodes.h).
Aabb blockBounds(const Skeleton& sk);

// The ground at (x, y): the highest bottom of the blocks nearest to (x, y) in plan (those within a
// metre of the nearest: a street's middle lies between two blocks, or on both their sides). A
// block's box reaches down to its ground, its lowest corner; the store's box does not tell where
// the streets are (cells' underlays lie below it, and a city far from its frame's origin drops with
// the earth's curvature towards its edges: 31 m at 20 km). On such a city a block's ground tilts,
// and the estimate is low by at most the tilt across one block (0.3 m for 100 m blocks 20 km from
// the origin).
double streetGround(const Skeleton& sk, double x, double y);

// The street generators read the model as a z-up city (streets in X and Y, heights in Z): an
// Error naming `kind` and suggesting the orbit when the store is not z-up, or lies on the earth
// in earth-centred coordinates.
Status requireZUp(const char* kind, const Skeleton& sk);

}  // namespace hlod
