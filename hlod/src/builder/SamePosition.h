#pragma once
// Vertices at one position, found by sorting (private to builder/): a hash map of positions
// allocates and hashes per vertex, and the builder asks this of every piece it simplifies.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace hlod {

// Per position, the index of the first (lowest) one equal to it: itself when it is the first.
// -0.0 and 0.0 are equal; a position with a NaN equals none.
std::vector<std::uint32_t> firstAtSamePosition(std::span<const glm::dvec3> positions);

}  // namespace hlod
