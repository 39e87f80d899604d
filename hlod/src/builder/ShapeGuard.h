#pragma once
// Keeps a reduced shape true to the original (private to build/).
#include <functional>

#include "hlod/builder/Simplifier.h"

namespace hlod {

using ReduceFn = std::function<Simplifier::ReducedShape(const Simplifier::Shape&,
                                                        std::size_t target, double errorLimit)>;

// Reduces shape toward targetTriangles with reduce (vertex clustering finishes where it stalls,
// within errorLimit), then checks the result against the shape's own triangles and repairs it
// (see the .cpp): no part of the surface is left farther than errorLimit from it.
// clusterEveryRound: clustering may finish the repair rounds too (Simplifier::simplifyUnion).
Simplifier::ReducedShape guardedReduce(const Simplifier::Shape& shape, std::size_t targetTriangles,
                                       double errorLimit, const ReduceFn& reduce,
                                       bool clusterEveryRound = false);

}  // namespace hlod
