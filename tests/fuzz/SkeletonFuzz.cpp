// skeleton.bin: the input is a whole skeleton file whose last 8 bytes (the checksum) the target
// rewrites to match, so that the fuzzer reaches the structure checks behind the checksum
// instead of stopping at it. A decoded skeleton must hold what decodeSkeleton guarantees (the
// rest of hlodr asserts it): checked here, an abort when it does not.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "FuzzSupport.h"
#include "hlod/store/NodeStore.h"
#include "store/ByteIO.h"

namespace {

void checkGuarantees(const hlod::DecodedSkeleton& d) {
  const auto& s = d.skeleton;
  const auto count = s.nodes.size();
  std::size_t parentless = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const auto& n = s.nodes[i];
    if (n.parent == hlod::kNoNode) {
      ++parentless;
      if (n.level != 0) std::abort();
    } else if (n.parent >= i || s.nodes[n.parent].level + 1 != n.level) {
      std::abort();
    }
    if (n.childCount > 0 &&
        (n.firstChild <= i || std::uint64_t(n.firstChild) + n.childCount > count))
      std::abort();
    for (std::uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c)
      if (s.nodes[c].parent != i) std::abort();
    // Both sections inside payload.bin (the texture may be another node's, shared).
    const std::uint64_t file = d.facts.payloadBytes;
    if (n.textureSize > n.payloadSize || n.payloadOffset > file ||
        n.meshSize() > file - n.payloadOffset || n.textureOffset > file ||
        n.textureSize > file - n.textureOffset)
      std::abort();
    if (!std::isfinite(n.cost) || !std::isfinite(n.staticBenefit) || !std::isfinite(n.centre.x))
      std::abort();
  }
  if (parentless != s.roots.size()) std::abort();
  for (auto r : s.roots)
    if (r >= count || s.nodes[r].parent != hlod::kNoNode) std::abort();
  if (!(s.params.levelFactor >= 2 && s.params.levelFactor <= 64) || s.params.desiredTri < 1 ||
      !(s.params.cTex >= 0 && s.params.cTex <= 1) || !std::isfinite(d.facts.buildSeconds))
    std::abort();
  // The model frame reaches camera paths and the terminal (`hlodr info`).
  if (static_cast<std::uint32_t>(s.up) > 2 || s.crs.description.size() > hlod::kMaxCrsDescription)
    std::abort();
  for (const unsigned char c : s.crs.description)
    if (c < 0x20 || c >= 0x7f) std::abort();
  // The quadtree hides no root from the selectors: roots ascending, each in exactly one leaf
  // cell whose box holds its own, the cell its anchor gives.
  for (std::size_t i = 1; i < s.roots.size(); ++i)
    if (s.roots[i] <= s.roots[i - 1]) std::abort();
  const auto& q = s.quadtree;
  if (q.empty()) return;
  std::vector<int> seen(count, 0);
  for (const auto& c : q.cells) {
    if (c.childCount > 0 && c.blockCount > 0) std::abort();
    for (std::uint32_t k = c.firstChild; k < c.firstChild + c.childCount; ++k)
      if (k >= q.cells.size()) std::abort();
    for (std::uint32_t k = c.firstBlock; k < c.firstBlock + c.blockCount; ++k) {
      if (k >= q.blocks.size()) std::abort();
      const auto& b = q.blocks[k];
      if (b.root >= count || s.nodes[b.root].parent != hlod::kNoNode) std::abort();
      ++seen[b.root];
      const auto& box = s.nodes[b.root].bounds;
      if (box.min.x < c.bounds.min.x || box.max.z > c.bounds.max.z) std::abort();
      if (hlod::quadCellAt(q.rect, q.depth, b.anchor) != glm::uvec2(c.x, c.y)) std::abort();
    }
  }
  for (auto r : s.roots)
    if (seen[r] != 1) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::byte> bytes(size);
  if (size > 0) std::memcpy(bytes.data(), data, size);
  if (size >= 16) {
    const std::uint64_t sum =
        hlod::store::fnv1a64(std::span<const std::byte>(bytes).first(size - 8));
    std::memcpy(bytes.data() + size - 8, &sum, 8);
  }
  auto decoded = hlod::decodeSkeleton(bytes);
  fuzz::report("decodeSkeleton", decoded);
  if (decoded.ok()) checkGuarantees(*decoded);
  return 0;
}
