// skeleton.bin encoding and checked decoding (format in hlod/store/NodeStore.h).
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

constexpr std::size_t kNodeRecordSize =
    5 * 4 + 9 * 8 + 4 * 4 + 2 * 8 + 3 * 4 + 8 + 2 * 8 + 4 + 8 + 8 + 8 + 4 + 8;

bool finite3(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

Error bad(const std::string& what) {
  return makeError("corrupt skeleton.bin: " + what);
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
  if (std::uint64_t(nodeCount) * kNodeRecordSize + std::uint64_t(rootCount) * 4 != r.remaining())
    return bad("node count does not match the file size");
  if (rootCount > nodeCount) return bad("more roots than nodes");
  s.nodes.resize(nodeCount);
  for (auto& n : s.nodes)
    if (!getNode(r, n)) return bad("truncated node records");
  s.roots.resize(rootCount);
  for (auto& root : s.roots)
    if (!r.get(root)) return bad("truncated root list");

  // Structure: children contiguous after their parent, parent links consistent, levels
  // increasing by one, payloads inside payload.bin. This also rules out cycles.
  std::uint64_t parentless = 0;
  for (std::uint32_t i = 0; i < nodeCount; ++i) {
    const NodeInfo& n = s.nodes[i];
    if (n.parent == kNoNode) {
      ++parentless;
      if (n.level != 0) return bad("root node " + std::to_string(i) + " has a non-zero level");
    } else if (n.parent >= i) {
      return bad("node " + std::to_string(i) + " has a bad parent");
    } else {
      const NodeInfo& p = s.nodes[n.parent];
      if (i < p.firstChild || i - p.firstChild >= p.childCount || n.level != p.level + 1)
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
    if (root >= nodeCount || s.nodes[root].parent != kNoNode) return bad("bad root list");
  return out;
}

}  // namespace hlod
