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

// The street generators read the model as a z-up city (streets in X and Y, heights in Z): an
// Error naming `kind` and suggesting the orbit when the store is not z-up.
Status requireZUp(const char* kind, const Skeleton& sk);

}  // namespace hlod
