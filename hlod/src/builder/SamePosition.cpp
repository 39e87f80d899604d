#include "builder/SamePosition.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

namespace hlod {

std::vector<std::uint32_t> firstAtSamePosition(std::span<const glm::dvec3> positions) {
  // The positions' bytes (zeros of either sign made +0.0) with the index: sorted, equal positions
  // lie in a run that starts at the lowest index.
  static_assert(sizeof(glm::dvec3) == 3 * sizeof(std::uint64_t));
  struct Key {
    std::array<std::uint64_t, 3> bits;
    std::uint32_t index;
    bool operator<(const Key& o) const {
      for (int k = 0; k < 3; ++k)
        if (bits[k] != o.bits[k]) return bits[k] < o.bits[k];
      return index < o.index;
    }
  };
  const auto n = static_cast<std::uint32_t>(positions.size());
  std::vector<std::uint32_t> first(n);
  std::vector<Key> keys;
  keys.reserve(n);
  for (std::uint32_t v = 0; v < n; ++v) {
    first[v] = v;
    const glm::dvec3 p = positions[v] + glm::dvec3(0.0);
    if (std::isnan(p.x) || std::isnan(p.y) || std::isnan(p.z)) continue;
    Key k{{}, v};
    std::memcpy(k.bits.data(), &p, sizeof p);
    keys.push_back(k);
  }
  std::sort(keys.begin(), keys.end());
  for (std::size_t i = 1; i < keys.size(); ++i)
    if (keys[i].bits == keys[i - 1].bits) first[keys[i].index] = first[keys[i - 1].index];
  return first;
}

}  // namespace hlod
