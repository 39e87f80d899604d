// skeleton.bin encoding and checked decoding (format in hlod/store/NodeStore.h).
#include <algorithm>
#include <cmath>
#include <cstring>

#include "hlod/store/NodeStore.h"
#include "store/ByteIO.h"

namespace hlod {

namespace {

constexpr char kSkeletonMagic[8] = {'H', 'L', 'O', 'D', 'S', 'K', 'E', 'L'};
constexpr std::uint32_t kByteOrderMark = 0x01020304u;
constexpr std::uint32_t kMaxSimplifierName = 64;

bool printableAscii(unsigned char c) {
  return c >= 0x20 && c < 0x7f;
}

// What the encoder writes of a CRS description: printable ASCII only, at most
// kMaxCrsDescription bytes, so that the decoder can refuse anything else.
std::string storableText(const std::string& text) {
  std::string out = text.substr(0, kMaxCrsDescription);
  for (char& c : out)
    if (!printableAscii(static_cast<unsigned char>(c))) c = '?';
  return out;
}

void putFrame(store::ByteWriter& w, const Skeleton& s) {
  w.put(static_cast<std::uint32_t>(s.up));
  w.put(std::int32_t(s.crs.epsg));
  w.put(std::uint32_t(s.crs.toEnu ? 1 : 0));
  w.put(s.crs.originLat);
  w.put(s.crs.originLon);
  w.put(s.crs.originHeight);
  const std::string text = storableText(s.crs.description);
  w.put(std::uint32_t(text.size()));
  w.putBytes(text.data(), text.size());
}

void putNode(store::ByteWriter& w, const NodeInfo& n) {
  w.put(n.parent);
  w.put(n.firstChild);
  w.put(n.childCount);
  w.put(n.level);
  w.put(n.block);
  w.put(n.bounds.min);
  w.put(n.bounds.max);
  w.put(n.centre);
  w.put(n.numTri);
  w.put(n.numTexTri);
  w.put(n.minTri);
  w.put(n.splatCount);
  w.put(n.cost);
  w.put(n.staticBenefit);
  w.put(n.avgNormal);
  w.put(n.geometricError);
  w.put(n.payloadOffset);
  w.put(n.payloadSize);
  w.put(n.payloadChecksum);
  w.put(n.memoryBytes);
  w.put(n.textureOffset);
  w.put(n.textureSize);
  w.put(n.textureChecksum);
  w.put(n.textureBytes);
}

bool getNode(store::ByteReader& r, NodeInfo& n) {
  return r.get(n.parent) && r.get(n.firstChild) && r.get(n.childCount) && r.get(n.level) &&
         r.get(n.block) && r.get(n.bounds.min) && r.get(n.bounds.max) && r.get(n.centre) &&
         r.get(n.numTri) && r.get(n.numTexTri) && r.get(n.minTri) && r.get(n.splatCount) &&
         r.get(n.cost) && r.get(n.staticBenefit) && r.get(n.avgNormal) && r.get(n.geometricError) &&
         r.get(n.payloadOffset) && r.get(n.payloadSize) && r.get(n.payloadChecksum) &&
         r.get(n.memoryBytes) && r.get(n.textureOffset) && r.get(n.textureSize) &&
         r.get(n.textureChecksum) && r.get(n.textureBytes);
}

void putQuadtree(store::ByteWriter& w, const BlockQuadtree& q) {
  w.put(static_cast<std::uint32_t>(q.domain));
  w.put(q.rect.minU);
  w.put(q.rect.minV);
  w.put(q.rect.maxU);
  w.put(q.rect.maxV);
  w.put(q.depth);
  w.put(std::uint32_t(q.cells.size()));
  w.put(std::uint32_t(q.blocks.size()));
  for (const QuadCell& c : q.cells) {
    w.put(c.level);
    w.put(c.x);
    w.put(c.y);
    w.put(c.firstChild);
    w.put(c.childCount);
    w.put(c.firstBlock);
    w.put(c.blockCount);
    w.put(c.bounds.min);
    w.put(c.bounds.max);
  }
  for (const QuadBlock& b : q.blocks) {
    w.put(b.root);
    w.put(b.anchor);
  }
}

constexpr std::size_t kQuadCellRecordSize = 7 * 4 + 6 * 8;
constexpr std::size_t kQuadBlockRecordSize = 4 + 2 * 8;

constexpr std::size_t kNodeRecordSize =
    5 * 4 + 9 * 8 + 4 * 4 + 2 * 8 + 3 * 4 + 8 + 2 * 8 + 4 + 8 + 8 + 8 + 4 + 8;

bool finite3(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

Error bad(const std::string& what) {
  return makeError("corrupt skeleton.bin: " + what);
}

bool contains(const Aabb& outer, const Aabb& inner) {
  return inner.empty() || (!outer.empty() && glm::all(glm::lessThanEqual(outer.min, inner.min)) &&
                           glm::all(glm::lessThanEqual(inner.max, outer.max)));
}

// The block quadtree after the root list. Culling trusts it to hide nothing: every root once,
// in the leaf cell its anchor falls in, each cell's box holding its blocks' and children's.
Status decodeQuadtree(store::ByteReader& r, Skeleton& s) {
  BlockQuadtree& q = s.quadtree;
  std::uint32_t domain = 0, cellCount = 0, blockCount = 0;
  if (!r.get(domain) || !r.get(q.rect.minU) || !r.get(q.rect.minV) || !r.get(q.rect.maxU) ||
      !r.get(q.rect.maxV) || !r.get(q.depth) || !r.get(cellCount) || !r.get(blockCount))
    return bad("truncated quadtree header");
  if (domain > 2) return bad("quadtree domain " + std::to_string(domain) + " is not 0, 1 or 2");
  q.domain = static_cast<QuadtreeDomain>(domain);
  if (std::uint64_t(cellCount) * kQuadCellRecordSize +
          std::uint64_t(blockCount) * kQuadBlockRecordSize !=
      r.remaining())
    return bad("quadtree cell and block counts do not match the file size");
  if (q.domain == QuadtreeDomain::None) {
    if (cellCount || blockCount) return bad("quadtree without a domain has cells");
    return Ok{};
  }
  if (q.depth > kMaxQuadtreeDepth) return bad("quadtree deeper than 30 levels");
  if (q.domain == QuadtreeDomain::Geographic && !(q.rect == kWholeGlobe))
    return bad("geographic quadtree does not cover the globe");
  if (!std::isfinite(q.rect.minU) || !std::isfinite(q.rect.minV) ||
      !std::isfinite(q.rect.maxU - q.rect.minU) || !std::isfinite(q.rect.maxV - q.rect.minV) ||
      !(q.rect.maxU > q.rect.minU) || !(q.rect.maxV > q.rect.minV))
    return bad("quadtree rectangle is not a finite, non-empty rectangle");
  const std::vector<std::uint32_t> blockRoots = s.blockRoots();
  if (cellCount == 0 || blockCount != blockRoots.size())
    return bad("quadtree does not hold one block per hlod_0 node");
  q.cells.resize(cellCount);
  for (QuadCell& c : q.cells)
    if (!r.get(c.level) || !r.get(c.x) || !r.get(c.y) || !r.get(c.firstChild) ||
        !r.get(c.childCount) || !r.get(c.firstBlock) || !r.get(c.blockCount) ||
        !r.get(c.bounds.min) || !r.get(c.bounds.max))
      return bad("truncated quadtree cells");
  q.blocks.resize(blockCount);
  for (QuadBlock& b : q.blocks)
    if (!r.get(b.root) || !r.get(b.anchor)) return bad("truncated quadtree blocks");

  // The tree: the root at level 0, each other cell the child of exactly one cell before it,
  // in one quadrant of it; leaves at `depth` with blocks, inner cells without.
  if (q.cells[0].level != 0 || q.cells[0].x != 0 || q.cells[0].y != 0)
    return bad("quadtree root is not cell (0, 0) at level 0");
  std::vector<std::uint8_t> owned(cellCount, 0), placed(blockCount, 0);
  for (std::uint32_t i = 0; i < cellCount; ++i) {
    const QuadCell& c = q.cells[i];
    const std::string name = "quadtree cell " + std::to_string(i);
    if (i > 0 && !owned[i]) return bad(name + " has no parent");
    if (c.level > q.depth || (c.level < 32 && (c.x >> c.level || c.y >> c.level)))
      return bad(name + " lies outside its level");
    if (c.bounds.empty() || !finite3(c.bounds.min) || !finite3(c.bounds.max))
      return bad(name + " has no finite box");
    if (c.childCount > 0) {
      if (c.blockCount > 0 || c.childCount > 4 || c.firstChild <= i || c.firstChild > cellCount ||
          c.childCount > cellCount - c.firstChild)
        return bad(name + " has children out of range");
      for (std::uint32_t k = c.firstChild; k < c.firstChild + c.childCount; ++k) {
        const QuadCell& child = q.cells[k];
        if (owned[k]++ || child.level != c.level + 1 || child.x >> 1 != c.x ||
            child.y >> 1 != c.y ||
            (k > c.firstChild && (child.y & 1) * 2 + (child.x & 1) <=
                                     (q.cells[k - 1].y & 1) * 2 + (q.cells[k - 1].x & 1)))
          return bad(name + " has a child outside its quadrants");
        if (!contains(c.bounds, child.bounds)) return bad(name + " box misses a child's");
      }
      continue;
    }
    if (c.level != q.depth || c.blockCount == 0 || c.firstBlock > blockCount ||
        c.blockCount > blockCount - c.firstBlock)
      return bad(name + " is a leaf without blocks at the quadtree's depth");
    for (std::uint32_t k = c.firstBlock; k < c.firstBlock + c.blockCount; ++k) {
      const QuadBlock& b = q.blocks[k];
      if (placed[k]++) return bad("quadtree block " + std::to_string(k) + " is in two cells");
      if (!std::isfinite(b.anchor.x) || !std::isfinite(b.anchor.y) || b.anchor.x < q.rect.minU ||
          b.anchor.x > q.rect.maxU || b.anchor.y < q.rect.minV || b.anchor.y > q.rect.maxV ||
          quadCellAt(q.rect, q.depth, b.anchor) != glm::uvec2(c.x, c.y))
        return bad("quadtree block " + std::to_string(k) + " is not in its anchor's cell");
      const auto at = std::lower_bound(blockRoots.begin(), blockRoots.end(), b.root);
      if (at == blockRoots.end() || *at != b.root)
        return bad("quadtree block " + std::to_string(k) + " is not a block's hlod_0 node");
      const Aabb& box = s.nodes[b.root].bounds;
      if (box.empty() || !contains(c.bounds, box)) return bad(name + " box misses a block's");
    }
  }
  // Every block in a cell, no root twice: then every root once (as many blocks as roots).
  if (std::find(placed.begin(), placed.end(), 0) != placed.end())
    return bad("quadtree block in no cell");
  std::vector<std::uint32_t> roots;
  for (const QuadBlock& b : q.blocks) roots.push_back(b.root);
  std::sort(roots.begin(), roots.end());
  if (std::adjacent_find(roots.begin(), roots.end()) != roots.end())
    return bad("quadtree holds a root twice");
  return Ok{};
}

}  // namespace

std::vector<std::byte> encodeSkeleton(const Skeleton& s, const StoreFacts& facts) {
  store::ByteWriter w;
  w.putBytes(kSkeletonMagic, sizeof kSkeletonMagic);
  w.put(kSkeletonFormatVersion);
  w.put(kByteOrderMark);
  w.put(s.params.levelFactor);
  w.put(s.params.desiredTri);
  w.put(s.params.cTex);
  const std::uint32_t nameLen =
      std::uint32_t(std::min<std::size_t>(s.params.simplifier.size(), kMaxSimplifierName));
  w.put(nameLen);
  w.putBytes(s.params.simplifier.data(), nameLen);
  w.put(facts.inputTriangles);
  w.put(facts.blockCount);
  w.put(facts.buildSeconds);
  w.put(facts.payloadBytes);
  putFrame(w, s);
  w.put(std::uint32_t(s.nodes.size()));
  w.put(std::uint32_t(s.roots.size()));
  for (const auto& n : s.nodes) putNode(w, n);
  for (std::uint32_t r : s.roots) w.put(r);
  putQuadtree(w, s.quadtree);
  w.put(store::fnv1a64(w.bytes));
  return std::move(w.bytes);
}

Result<DecodedSkeleton> decodeSkeleton(std::span<const std::byte> bytes) {
  if (bytes.size() < sizeof kSkeletonMagic + 8 + 8) return bad("file too short");
  if (std::memcmp(bytes.data(), kSkeletonMagic, sizeof kSkeletonMagic) != 0)
    return bad("not a node store skeleton (bad magic)");
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  const auto body = bytes.first(bytes.size() - 8);
  store::ByteReader r(body);
  char magic[8];
  std::uint32_t version = 0, bom = 0;
  (void)r.getBytes(magic, 8);
  if (!r.get(version) || !r.get(bom)) return bad("truncated header");
  if (version != kSkeletonFormatVersion)
    return makeError("skeleton.bin format version " + std::to_string(version) +
                     " is not supported (this hlodr reads " +
                     std::to_string(kSkeletonFormatVersion) + "; rebuild it with hlodr build)");
  if (bom != kByteOrderMark) return bad("byte order mark (written on another architecture?)");
  if (store::fnv1a64(body) != stored) return bad("checksum mismatch");

  DecodedSkeleton out;
  Skeleton& s = out.skeleton;
  std::uint32_t nameLen = 0, nodeCount = 0, rootCount = 0, up = 0, toEnu = 0, textLen = 0;
  std::int32_t epsg = 0;
  if (!r.get(s.params.levelFactor) || !r.get(s.params.desiredTri) || !r.get(s.params.cTex) ||
      !r.get(nameLen) || nameLen > kMaxSimplifierName)
    return bad("truncated build parameters");
  s.params.simplifier.resize(nameLen);
  if (!r.getBytes(s.params.simplifier.data(), nameLen) || !r.get(out.facts.inputTriangles) ||
      !r.get(out.facts.blockCount) || !r.get(out.facts.buildSeconds) ||
      !r.get(out.facts.payloadBytes))
    return bad("truncated header");
  if (!r.get(up) || !r.get(epsg) || !r.get(toEnu) || !r.get(s.crs.originLat) ||
      !r.get(s.crs.originLon) || !r.get(s.crs.originHeight) || !r.get(textLen) ||
      textLen > kMaxCrsDescription)
    return bad("truncated model frame (up axis, CRS)");
  s.crs.description.resize(textLen);
  if (!r.getBytes(s.crs.description.data(), textLen) || !r.get(nodeCount) || !r.get(rootCount))
    return bad("truncated header");
  // The frame reaches `hlodr info` and every camera path: only values an import can give.
  if (up > 2) return bad("up axis " + std::to_string(up) + " is not 0, 1 or 2 (x, y, z)");
  s.up = static_cast<UpAxis>(up);
  if (epsg < 0) return bad("negative EPSG code");
  s.crs.epsg = epsg;
  if (toEnu > 1) return bad("CRS conversion flag is not 0 or 1");
  s.crs.toEnu = toEnu == 1;
  if (!(std::abs(s.crs.originLat) <= 90.0) || !(std::abs(s.crs.originLon) <= 180.0) ||
      !std::isfinite(s.crs.originHeight))
    return bad("CRS origin is not a latitude, longitude and finite height");
  for (const char c : s.crs.description)
    if (!printableAscii(static_cast<unsigned char>(c)))
      return bad("CRS description holds a byte that is not printable ASCII");
  // The ranges HlodBuilder::create accepts: `hlodr info` once printed nan and inf from here.
  // (The simplifier name is any bytes; printing it is the printer's care.)
  if (!(s.params.levelFactor >= 2.0 && s.params.levelFactor <= 64.0))
    return bad("build parameter levelFactor is not in [2, 64]");
  if (s.params.desiredTri < 1) return bad("build parameter desiredTri is 0");
  if (!(s.params.cTex >= 0.0 && s.params.cTex <= 1.0))
    return bad("build parameter c_tex is not in [0, 1]");
  if (!(out.facts.buildSeconds >= 0.0 && std::isfinite(out.facts.buildSeconds)))
    return bad("build time is not a finite number of seconds");
  if (std::uint64_t(nodeCount) * kNodeRecordSize + std::uint64_t(rootCount) * 4 > r.remaining())
    return bad("node count does not match the file size");
  if (rootCount > nodeCount) return bad("more roots than nodes");
  s.nodes.resize(nodeCount);
  for (auto& n : s.nodes)
    if (!getNode(r, n)) return bad("truncated node records");
  s.roots.resize(rootCount);
  for (auto& root : s.roots)
    if (!r.get(root)) return bad("truncated root list");

  // Structure: children contiguous after their parent, parent links consistent, levels
  // increasing by one below a block's node (0 below a cell node, cell nodes only below cell
  // nodes), payloads inside payload.bin. This also rules out cycles.
  std::uint64_t parentless = 0, cells = 0;
  for (std::uint32_t i = 0; i < nodeCount; ++i) {
    const NodeInfo& n = s.nodes[i];
    if (n.isCell()) {
      ++cells;
      if (n.level != 0 || n.childCount == 0)
        return bad("cell node " + std::to_string(i) + " has a level or no children");
    }
    if (n.parent == kNoNode) {
      ++parentless;
      if (n.level != 0) return bad("root node " + std::to_string(i) + " has a non-zero level");
    } else if (n.parent >= i) {
      return bad("node " + std::to_string(i) + " has a bad parent");
    } else {
      const NodeInfo& p = s.nodes[n.parent];
      if (i < p.firstChild || i - p.firstChild >= p.childCount ||
          n.level != (p.isCell() ? 0 : p.level + 1) || (n.isCell() && !p.isCell()))
        return bad("node " + std::to_string(i) + " is not among its parent's children");
    }
    if (n.childCount > 0) {
      if (n.firstChild <= i || n.firstChild > nodeCount || n.childCount > nodeCount - n.firstChild)
        return bad("node " + std::to_string(i) + " has children out of range");
      for (std::uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c)
        if (s.nodes[c].parent != i)
          return bad("child of node " + std::to_string(i) + " disowns it");
    }
    // Both sections inside payload.bin (the texture one may be another node's: shared).
    const std::uint64_t file = out.facts.payloadBytes;
    if (n.textureSize > n.payloadSize || n.payloadOffset > file ||
        n.meshSize() > file - n.payloadOffset || n.textureOffset > file ||
        n.textureSize > file - n.textureOffset || (n.textureSize == 0 && n.textureOffset != 0))
      return bad("node " + std::to_string(i) + " payload lies outside payload.bin");
    // DEFLATE expands at most 1032:1; a larger claim would only make a load allocate wildly.
    if (n.memoryBytes > 1032 * n.payloadSize + 1024)
      return bad("node " + std::to_string(i) + " claims an impossible decoded size");
    // The texture section decodes to the tail of the decoded bytes.
    if ((n.textureSize > 0 && n.textureSize >= n.payloadSize) ||
        (n.textureBytes > 0 && n.textureBytes >= n.memoryBytes) ||
        (n.textureSize == 0) != (n.textureBytes == 0) ||
        n.textureBytes > 1032 * n.textureSize + 1024 ||
        n.memoryBytes - n.textureBytes > 1032 * (n.payloadSize - n.textureSize) + 1024)
      return bad("node " + std::to_string(i) + " has an impossible texture section");
    if (!finite3(n.centre) ||
        (!n.bounds.empty() && (!finite3(n.bounds.min) || !finite3(n.bounds.max))) ||
        !std::isfinite(n.cost) || !std::isfinite(n.staticBenefit) ||
        !std::isfinite(n.geometricError) || !std::isfinite(n.avgNormal.x) ||
        !std::isfinite(n.avgNormal.y) || !std::isfinite(n.avgNormal.z) || n.numTexTri > n.numTri ||
        n.minTri > n.numTri)
      return bad("node " + std::to_string(i) + " holds impossible values");
  }
  if (parentless != rootCount) return bad("root list does not match the parentless nodes");
  for (std::uint32_t root : s.roots)
    if (root >= nodeCount || s.nodes[root].parent != kNoNode ||
        (cells > 0 && !s.nodes[root].isCell()))
      return bad("bad root list (with cell nodes, every root is one)");
  // Ascending (as the builder writes them): no root twice, and the quadtree walk can hand the
  // selectors its roots in this order by sorting them.
  for (std::size_t i = 1; i < s.roots.size(); ++i)
    if (s.roots[i] <= s.roots[i - 1]) return bad("root list is not in ascending order");
  if (auto q = decodeQuadtree(r, s); !q) return q.error();
  if (r.remaining() != 0) return bad("bytes after the quadtree");
  return out;
}

}  // namespace hlod
