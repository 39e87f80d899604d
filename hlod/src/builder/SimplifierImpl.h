#pragma once
// The three Simplifier implementations (private; use makeSimplifier), and what they share.
#include <cstdint>
#include <cstring>

#include "hlod/builder/Simplifier.h"

namespace hlod {

// FNV-1a over a position's bytes: exact equality, as welding by position needs. Callers add
// glm::dvec3(0.0) to keys first so that -0.0 and 0.0 hash alike.
struct PositionHash {
  std::size_t operator()(const glm::dvec3& p) const {
    unsigned char bytes[sizeof p];
    std::memcpy(bytes, &p, sizeof p);
    std::uint64_t h = 1469598103934665603ull;
    for (unsigned char b : bytes) h = (h ^ b) * 1099511628211ull;
    return std::size_t(h);
  }
};

Simplifier* makeMeshoptSimplifier();
Simplifier* makeOpenMeshSimplifier();
Simplifier* makeParrySimplifier();

}  // namespace hlod
