#include "hlod/Progression.h"

#include <cassert>
#include <numeric>
#include <utility>

namespace hlod {

std::size_t Progression::decimated() const {
  return std::accumulate(increments.begin(), increments.end(), std::size_t(0));
}

std::vector<std::uint32_t> progressiveIndices(std::span<const std::uint32_t> indices,
                                              const Progression& progression, std::size_t n,
                                              std::size_t vertexCount) {
  const std::size_t triangles = indices.size() / 3;
  assert(n <= triangles && triangles - n <= progression.decimated());
  assert(progression.moveEnd.size() == progression.increments.size());
  const std::size_t start = triangles - n;
  // reference[v]: the vertex v was combined into (v itself while it stands).
  std::vector<std::uint32_t> reference(vertexCount);
  std::iota(reference.begin(), reference.end(), 0u);
  std::size_t decimated = 0, move = 0;  // triangles before the next combination's; its moves
  for (std::size_t j = 0; j < progression.increments.size() && decimated < start; ++j) {
    for (; move < progression.moveEnd[j]; ++move) {
      const std::uint32_t v = progression.moves[2 * move], into = progression.moves[2 * move + 1];
      assert(v < vertexCount && into < vertexCount);
      reference[v] = into;
    }
    decimated += progression.increments[j];
  }
  const auto find = [&](std::uint32_t v) {
    std::uint32_t r = v;
    while (reference[r] != r) r = reference[r];
    while (reference[v] != r) v = std::exchange(reference[v], r);  // path compression
    return r;
  };
  std::vector<std::uint32_t> out(indices.begin() + 3 * start, indices.end());
  for (std::uint32_t& v : out) {
    assert(v < vertexCount);
    v = find(v);
  }
  return out;
}

}  // namespace hlod
