// Encoding and strict decoding of node payloads (format in hlod/store/NodeStore.h).
#include <libdeflate.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <new>

#include "hlod/store/NodeStore.h"
#include "store/ByteIO.h"

namespace hlod {

namespace {

constexpr std::uint32_t kPayloadMagic = 0x4c504c48u;  // "HLPL"
constexpr std::uint32_t kFlagTexCoords = 1u;
constexpr std::uint32_t kFlagOneSided = 2u;     // Mesh::oneSided
constexpr std::uint32_t kFlagProgression = 4u;  // Mesh::progression (since format 3)
constexpr std::uint32_t kFlagSplats = 8u;       // LocalMesh::splats (since format 3)
constexpr std::uint64_t kMaxSplats = 1u << 24;
// Generous limits that still keep every size computation far from overflow.
constexpr std::uint64_t kMaxVertices = 1ull << 28;
constexpr std::uint64_t kMaxIndices = 1ull << 30;
constexpr std::uint32_t kMaxTextureSide = 1u << 15;
constexpr std::uint64_t kMaxCombinations = kMaxVertices;
constexpr std::uint64_t kMaxMoves = 4 * kMaxVertices;
constexpr std::uint64_t kMaxPayloadBytes =
    7 * 4 + 16 + kMaxVertices * 32 + kMaxIndices * 4 + 4 + 8 + kMaxCombinations * 8 +
    kMaxMoves * 8 + 4 + kMaxSplats * 36 + 4ull * kMaxTextureSide * kMaxTextureSide;

struct CompressorFree {
  void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};
struct DecompressorFree {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

// A progression decoded from a store can be drawn (progressiveIndices' preconditions): every
// vertex in range, each moved at most once, never into itself or into a vertex already moved (so
// that references form a forest and no lookup loops), the combinations' move ranges in order, and
// no more triangles decimated than the mesh has.
bool validProgression(const Progression& p, std::uint32_t vertexCount, std::uint32_t triangles) {
  std::vector<std::uint8_t> moved(vertexCount, 0);
  std::uint64_t decimated = 0;
  std::size_t move = 0;
  for (std::size_t j = 0; j < p.increments.size(); ++j) {
    if (p.moveEnd[j] < move || p.moveEnd[j] > p.moves.size() / 2) return false;
    for (; move < p.moveEnd[j]; ++move) {
      const std::uint32_t v = p.moves[2 * move], into = p.moves[2 * move + 1];
      if (v >= vertexCount || into >= vertexCount || v == into || moved[v] || moved[into])
        return false;
      moved[v] = 1;
    }
    decimated += p.increments[j];
  }
  return move == p.moves.size() / 2 && decimated <= triangles;
}

bool allFinite(const float* v, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

}  // namespace

std::uint32_t crc32(std::span<const std::byte> bytes) {
  return std::uint32_t(libdeflate_crc32(0, bytes.data(), bytes.size()));
}

std::vector<std::byte> compressPayload(std::span<const std::byte> raw) {
  // Level 1, the fastest: the builder writes every node, and higher levels gain little size for
  // much more time.
  thread_local std::unique_ptr<libdeflate_compressor, CompressorFree> c(
      libdeflate_alloc_compressor(1));
  if (!c) throw std::bad_alloc();
  std::vector<std::byte> out(libdeflate_deflate_compress_bound(c.get(), raw.size()));
  const std::size_t n =
      libdeflate_deflate_compress(c.get(), raw.data(), raw.size(), out.data(), out.size());
  out.resize(n);  // never 0: the bound always fits
  return out;
}

Result<std::vector<std::byte>> inflatePayload(std::span<const std::byte> stored,
                                              std::uint64_t memoryBytes) {
  if (memoryBytes > kMaxPayloadBytes) return makeError("payload claims an impossible size");
  thread_local std::unique_ptr<libdeflate_decompressor, DecompressorFree> d(
      libdeflate_alloc_decompressor());
  if (!d) throw std::bad_alloc();
  std::vector<std::byte> raw(memoryBytes);
  // Exactly memoryBytes or an error: libdeflate never writes past the buffer.
  if (libdeflate_deflate_decompress(d.get(), stored.data(), stored.size(), raw.data(), raw.size(),
                                    nullptr) != LIBDEFLATE_SUCCESS)
    return makeError("payload does not decompress to its recorded size (corrupt store)");
  return raw;
}

std::vector<std::byte> encodePayload(const LocalMesh& mesh) {
  store::ByteWriter w;
  const std::uint32_t vc = std::uint32_t(mesh.positions.size());
  const bool hasUv = mesh.texCoords.size() == mesh.positions.size() && vc > 0;
  const bool hasTex =
      mesh.texture && !mesh.texture->empty() &&
      mesh.texture->pixels.size() == std::size_t(mesh.texture->width) * mesh.texture->height * 4;
  w.put(kPayloadMagic);
  w.put(kPayloadFormatVersion);
  w.put(vc);
  w.put(std::uint32_t(mesh.indices.size()));
  const bool hasProgression = !mesh.progression.empty();
  w.put((hasUv ? kFlagTexCoords : 0u) | (mesh.oneSided ? kFlagOneSided : 0u) |
        (hasProgression ? kFlagProgression : 0u) | (mesh.splats.empty() ? 0u : kFlagSplats));
  w.put(std::uint32_t(hasTex ? mesh.texture->width : 0));
  w.put(std::uint32_t(hasTex ? mesh.texture->height : 0));
  w.put(mesh.baseColor);
  w.putBytes(mesh.positions.data(), sizeof(glm::vec3) * vc);
  if (mesh.normals.size() == vc) {
    w.putBytes(mesh.normals.data(), sizeof(glm::vec3) * vc);
  } else {
    for (std::uint32_t i = 0; i < vc; ++i) w.put(glm::vec3(0, 0, 1));
  }
  if (hasUv) w.putBytes(mesh.texCoords.data(), sizeof(glm::vec2) * vc);
  w.putBytes(mesh.indices.data(), sizeof(std::uint32_t) * mesh.indices.size());
  if (hasProgression) {
    const Progression& p = mesh.progression;
    w.put(std::uint32_t(p.increments.size()));
    w.put(std::uint32_t(p.moves.size() / 2));
    w.putBytes(p.moves.data(), sizeof(std::uint32_t) * p.moves.size());
    w.putBytes(p.moveEnd.data(), sizeof(std::uint32_t) * p.moveEnd.size());
    w.putBytes(p.increments.data(), sizeof(std::uint32_t) * p.increments.size());
  }
  if (!mesh.splats.empty()) {
    static_assert(sizeof(Splat) == 36);
    w.put(std::uint32_t(mesh.splats.size()));
    w.putBytes(mesh.splats.data(), sizeof(Splat) * mesh.splats.size());
  }
  if (hasTex) w.putBytes(mesh.texture->pixels.data(), mesh.texture->pixels.size());
  return std::move(w.bytes);
}

Result<LocalMesh> decodePayloadBytes(std::span<const std::byte> bytes, const glm::dvec3& centre,
                                     bool pixels) {
  store::ByteReader r(bytes);
  std::uint32_t magic = 0, version = 0, vc = 0, ic = 0, flags = 0, tw = 0, th = 0;
  glm::vec4 baseColor;
  if (!r.get(magic) || !r.get(version) || !r.get(vc) || !r.get(ic) || !r.get(flags) || !r.get(tw) ||
      !r.get(th) || !r.get(baseColor))
    return makeError("payload truncated in its header");
  if (magic != kPayloadMagic) return makeError("payload has a bad magic number");
  // Format 2 is format 3 without progressions: both are read.
  if (version != kPayloadFormatVersion && version != 2)
    return makeError("payload format version " + std::to_string(version) + " is not supported");
  const std::uint32_t knownFlags =
      kFlagTexCoords | kFlagOneSided | (version >= 3 ? kFlagProgression | kFlagSplats : 0u);
  if (vc > kMaxVertices || ic > kMaxIndices || ic % 3 != 0 || (flags & ~knownFlags) ||
      tw > kMaxTextureSide || th > kMaxTextureSide || (tw == 0) != (th == 0))
    return makeError("payload header has impossible counts");
  const bool hasUv = flags & kFlagTexCoords;
  const bool hasProgression = flags & kFlagProgression;
  // The progression's count sits right after the indices: read it from there before the size
  // check, so that nothing is allocated for counts the bytes cannot hold.
  const std::uint64_t meshBytes =
      7 * 4 + 16 + std::uint64_t(vc) * (hasUv ? 32 : 24) + std::uint64_t(ic) * 4;
  // The same for the splats' count, after the progression.
  const bool hasSplats = flags & kFlagSplats;
  const auto countAt = [&](std::uint64_t offset, std::uint32_t& count, std::uint64_t max) {
    if (bytes.size() < offset + 4) return false;
    std::memcpy(&count, bytes.data() + offset, 4);
    return count > 0 && count <= max;
  };
  std::uint32_t combinations = 0, moves = 0, splats = 0;
  if (hasProgression && (!countAt(meshBytes, combinations, kMaxCombinations) ||
                         !countAt(meshBytes + 4, moves, kMaxMoves)))
    return makeError("payload has an impossible progression count");
  const std::uint64_t splatsAt =
      meshBytes +
      (hasProgression ? 8 + std::uint64_t(moves) * 8 + std::uint64_t(combinations) * 8 : 0);
  if (hasSplats && !countAt(splatsAt, splats, kMaxSplats))
    return makeError("payload has an impossible splat count");
  const std::uint64_t expected = splatsAt + (hasSplats ? 4 + std::uint64_t(splats) * 36 : 0) +
                                 (pixels ? std::uint64_t(tw) * th * 4 : 0);
  if (expected != bytes.size())
    return makeError("payload size " + std::to_string(bytes.size()) +
                     " does not match its counts (" + std::to_string(expected) + ")");
  LocalMesh m;
  m.centre = centre;
  m.baseColor = baseColor;
  m.oneSided = flags & kFlagOneSided;
  m.positions.resize(vc);
  m.normals.resize(vc);
  if (hasUv) m.texCoords.resize(vc);
  m.indices.resize(ic);
  if (!r.getBytes(m.positions.data(), std::uint64_t(vc) * 12) ||
      !r.getBytes(m.normals.data(), std::uint64_t(vc) * 12) ||
      (hasUv && !r.getBytes(m.texCoords.data(), std::uint64_t(vc) * 8)) ||
      !r.getBytes(m.indices.data(), std::uint64_t(ic) * 4))
    return makeError("payload truncated");
  if (hasProgression) {
    std::uint32_t count = 0, moveCount = 0;
    m.progression.moves.resize(std::size_t(moves) * 2);
    m.progression.moveEnd.resize(combinations);
    m.progression.increments.resize(combinations);
    if (!r.get(count) || !r.get(moveCount) ||
        !r.getBytes(m.progression.moves.data(), std::uint64_t(moves) * 8) ||
        !r.getBytes(m.progression.moveEnd.data(), std::uint64_t(combinations) * 4) ||
        !r.getBytes(m.progression.increments.data(), std::uint64_t(combinations) * 4))
      return makeError("payload truncated");
    if (!validProgression(m.progression, vc, ic / 3))
      return makeError("payload has an invalid progression (simplification arrays)");
  }
  if (hasSplats) {
    std::uint32_t count = 0;
    m.splats.resize(splats);
    if (!r.get(count) || !r.getBytes(m.splats.data(), std::uint64_t(splats) * 36))
      return makeError("payload truncated");
    if (!allFinite(reinterpret_cast<const float*>(m.splats.data()), m.splats.size() * 9))
      return makeError("payload holds a non-finite number");
    for (const Splat& splat : m.splats)
      if (!(splat.radius >= 0.0f)) return makeError("payload has a splat of negative radius");
  }
  if (tw > 0 && pixels) {
    auto img = std::make_shared<Image>();
    img->width = int(tw);
    img->height = int(th);
    img->pixels.resize(std::size_t(tw) * th * 4);
    if (!r.getBytes(img->pixels.data(), img->pixels.size())) return makeError("payload truncated");
    m.texture = std::move(img);
  }
  if (!allFinite(&baseColor.x, 4) ||
      !allFinite(reinterpret_cast<const float*>(m.positions.data()), m.positions.size() * 3) ||
      !allFinite(reinterpret_cast<const float*>(m.normals.data()), m.normals.size() * 3) ||
      !allFinite(reinterpret_cast<const float*>(m.texCoords.data()), m.texCoords.size() * 2))
    return makeError("payload holds a non-finite number");
  for (std::uint32_t i : m.indices)
    if (i >= vc) return makeError("payload index out of range");
  return m;
}

}  // namespace hlod
