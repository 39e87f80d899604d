#pragma once
// Keeps a reduced shape true to the original (private to build/).
#include <functional>

#include "hlod/Simplifier.h"

namespace hlod {

using ReduceFn =
    std::function<Simplifier::ReducedShape(const Simplifier::Shape&, std::size_t target)>;

// Reduces shape toward targetTriangles with reduce (vertex clustering finishes where it stalls),
// then checks the result against the shape's own triangles and repairs it (see the .cpp).
Simplifier::ReducedShape guardedReduce(const Simplifier::Shape& shape, std::size_t targetTriangles,
                                       const ReduceFn& reduce);

}  // namespace hlod
