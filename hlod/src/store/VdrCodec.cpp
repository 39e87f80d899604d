// Encoding and strict decoding of the view-dependent section (format in hlod/store/VdrStore.h).
#include <cmath>
#include <cstring>
#include <fstream>

#include "hlod/store/NodeStore.h"
#include "hlod/store/VdrStore.h"
#include "store/ByteIO.h"

namespace hlod {

namespace {

using vdr::kNone;

constexpr std::uint32_t kVdrRecordMagic = 0x44564c48u;  // "HLVD"
constexpr char kVdrIndexMagic[8] = {'H', 'L', 'O', 'D', 'V', 'D', 'R', 'I'};
constexpr char kVdrTrailerMagic[8] = {'H', 'L', 'O', 'D', 'V', 'D', 'R', '0'};
constexpr std::uint32_t kVdrFlagTexCoords = 1u, kVdrFlagOneSided = 2u, kVdrFlagTexture = 4u;
// Generous limits that keep every size computation far from overflow.
constexpr std::uint64_t kVdrMaxLeaves = 1ull << 27;
constexpr std::uint64_t kVdrMaxFaces = 1ull << 28;
constexpr std::uint64_t kVdrMaxStoredFaces = 1ull << 30;
constexpr std::uint32_t kVdrMaxTextureSide = 1u << 15;
constexpr std::uint64_t kVdrHeaderBytes = 11 * 4 + 3 * 8 + 4 * 4 + 8;
constexpr std::uint64_t kVdrClusterBytes = 5 * 4 + 2 * 4;
constexpr std::uint64_t kVdrEntryBytes = 4 + 3 * 8 + 4 + 6 * 8 + 3 * 4;
constexpr std::uint64_t kVdrTrailerBytes = 8 + 8 + 8;

template <class T>
bool finite(const T* v, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

}  // namespace

std::vector<std::byte> encodeVdrObject(const vdr::VdrObject& o) {
  const vdr::VertexHierarchy& h = o.hierarchy;
  const auto L = h.leafCount, V = h.vertexCount();
  const auto F = std::uint32_t(h.faces.size()), W = std::uint32_t(o.wedgeLeaf.size());
  const auto S = std::uint32_t(h.storedFaces.size());
  const auto K = std::uint32_t(o.clusters.clusters.size());
  const bool uv = o.wedgeTexCoord.size() == o.wedgeLeaf.size() && W > 0;
  const bool tex =
      uv && o.texture && !o.texture->empty() &&
      o.texture->pixels.size() == std::size_t(o.texture->width) * o.texture->height * 4;
  store::ByteWriter w;
  w.put(kVdrRecordMagic);
  w.put(kVdrRecordVersion);
  w.put((uv ? kVdrFlagTexCoords : 0u) | (o.oneSided ? kVdrFlagOneSided : 0u) |
        (tex ? kVdrFlagTexture : 0u));
  for (std::uint32_t n : {L, V, F, W, S, K}) w.put(n);
  w.put(std::uint32_t(tex ? o.texture->width : 0));
  w.put(std::uint32_t(tex ? o.texture->height : 0));
  w.put(o.centre);
  w.put(o.baseColor);
  w.put(o.clusters.errorFloor);
  for (const glm::dvec3& p : h.leafPosition) w.put(glm::vec3(p - o.centre));
  w.putBytes(h.children.data(), h.children.size() * 8);
  w.putBytes(h.error.data(), std::size_t(V) * 4);
  w.putBytes(h.radius.data(), std::size_t(V) * 4);
  w.putBytes(o.clusters.clusterOf.data(), std::size_t(V) * 4);
  w.putBytes(h.neighbourhoodStart.data(), h.neighbourhoodStart.size() * 4);
  for (const vdr::StoredFace& s : h.storedFaces) {
    w.put(s.face);
    w.put(s.corners);
  }
  w.putBytes(o.wedgeNormal.data(), std::size_t(W) * 12);
  if (uv) w.putBytes(o.wedgeTexCoord.data(), std::size_t(W) * 8);
  w.putBytes(o.wedgeLeaf.data(), std::size_t(W) * 4);
  w.putBytes(o.wedgeChart.data(), std::size_t(W) * 4);
  w.putBytes(o.faceWedges.data(), std::size_t(F) * 12);
  for (const vdr::Cluster& c : o.clusters.clusters) {
    w.put(c.parent);
    w.put(c.children);
    w.put(c.vertexCount);
    w.put(c.depth);
    w.put(c.minError);
    w.put(c.maxError);
  }
  if (tex) w.putBytes(o.texture->pixels.data(), o.texture->pixels.size());
  return std::move(w.bytes);
}

Result<vdr::VdrObject> decodeVdrObject(std::span<const std::byte> bytes) {
  store::ByteReader r(bytes);
  std::uint32_t magic = 0, version = 0, flags = 0, L = 0, V = 0, F = 0, W = 0, S = 0, K = 0, tw = 0,
                th = 0;
  vdr::VdrObject o;
  double floor = 0.0;
  if (!r.get(magic) || !r.get(version) || !r.get(flags) || !r.get(L) || !r.get(V) || !r.get(F) ||
      !r.get(W) || !r.get(S) || !r.get(K) || !r.get(tw) || !r.get(th) || !r.get(o.centre) ||
      !r.get(o.baseColor) || !r.get(floor))
    return makeError("view-dependent record truncated in its header");
  if (magic != kVdrRecordMagic) return makeError("view-dependent record has a bad magic number");
  if (version != kVdrRecordVersion)
    return makeError("view-dependent record version " + std::to_string(version) +
                     " is not supported (rebuild the store with --vdr)");
  const bool uv = flags & kVdrFlagTexCoords, tex = flags & kVdrFlagTexture;
  if ((flags & ~(kVdrFlagTexCoords | kVdrFlagOneSided | kVdrFlagTexture)) || L == 0 ||
      L > kVdrMaxLeaves || V < L || V - L >= L || F == 0 || F > kVdrMaxFaces || W < L ||
      W > 2 * kVdrMaxLeaves || S > kVdrMaxStoredFaces || K == 0 || K > V ||
      tw > kVdrMaxTextureSide || th > kVdrMaxTextureSide || (tw == 0) != (th == 0) ||
      tex != (tw > 0) || (tex && !uv))
    return makeError("view-dependent record has impossible counts");
  const std::uint64_t I = V - L;
  const std::uint64_t expected = kVdrHeaderBytes + 12ull * L + 8 * I + 12ull * V + 4 * (I + 1) +
                                 16ull * S + std::uint64_t(W) * (uv ? 28 : 20) + 12ull * F +
                                 kVdrClusterBytes * K + 4ull * tw * th;
  if (expected != bytes.size())
    return makeError("view-dependent record size " + std::to_string(bytes.size()) +
                     " does not match its counts (" + std::to_string(expected) + ")");
  if (!finite(&o.centre.x, 3) || !finite(&o.baseColor.x, 4) || !std::isfinite(floor) ||
      !(floor > 0.0))
    return makeError("view-dependent record holds a non-finite number");
  o.oneSided = flags & kVdrFlagOneSided;
  vdr::VertexHierarchy& h = o.hierarchy;
  h.leafCount = L;
  std::vector<glm::vec3> leaf(L);
  h.children.resize(I);
  h.error.resize(V);
  h.radius.resize(V);
  o.clusters.clusterOf.resize(V);
  o.clusters.errorFloor = floor;
  h.neighbourhoodStart.resize(I + 1);
  h.storedFaces.resize(S);
  o.wedgeNormal.resize(W);
  if (uv) o.wedgeTexCoord.resize(W);
  o.wedgeLeaf.resize(W);
  o.wedgeChart.resize(W);
  o.faceWedges.resize(F);
  o.clusters.clusters.resize(K);
  bool read = r.getBytes(leaf.data(), 12ull * L) && r.getBytes(h.children.data(), 8 * I) &&
              r.getBytes(h.error.data(), 4ull * V) && r.getBytes(h.radius.data(), 4ull * V) &&
              r.getBytes(o.clusters.clusterOf.data(), 4ull * V) &&
              r.getBytes(h.neighbourhoodStart.data(), 4 * (I + 1));
  for (vdr::StoredFace& s : h.storedFaces) read = read && r.get(s.face) && r.get(s.corners);
  read = read && r.getBytes(o.wedgeNormal.data(), 12ull * W) &&
         (!uv || r.getBytes(o.wedgeTexCoord.data(), 8ull * W)) &&
         r.getBytes(o.wedgeLeaf.data(), 4ull * W) && r.getBytes(o.wedgeChart.data(), 4ull * W) &&
         r.getBytes(o.faceWedges.data(), 12ull * F);
  for (vdr::Cluster& c : o.clusters.clusters)
    read = read && r.get(c.parent) && r.get(c.children) && r.get(c.vertexCount) && r.get(c.depth) &&
           r.get(c.minError) && r.get(c.maxError);
  if (tex) {
    auto img = std::make_shared<Image>();
    img->width = int(tw);
    img->height = int(th);
    img->pixels.resize(std::size_t(tw) * th * 4);
    read = read && r.getBytes(img->pixels.data(), img->pixels.size());
    o.texture = std::move(img);
  }
  if (!read) return makeError("view-dependent record truncated");

  // Numbers.
  if (!finite(&leaf[0].x, 3ull * L) || !finite(h.error.data(), V) || !finite(h.radius.data(), V) ||
      !finite(&o.wedgeNormal[0].x, 3ull * W) || (uv && !finite(&o.wedgeTexCoord[0].x, 2ull * W)))
    return makeError("view-dependent record holds a non-finite number");
  for (std::uint32_t v = 0; v < V; ++v)
    if (h.error[v] < 0.0f || h.radius[v] < 0.0f || (v < L && h.error[v] != 0.0f))
      return makeError("view-dependent record has a negative error or radius");
  h.leafPosition.resize(L);
  for (std::uint32_t l = 0; l < L; ++l) h.leafPosition[l] = o.centre + glm::dvec3(leaf[l]);
  // The tree: each child below its parent, each vertex one parent at most, errors monotone.
  h.parent.assign(V, kNone);
  h.leafOf.resize(V);
  for (std::uint32_t l = 0; l < L; ++l) h.leafOf[l] = l;
  for (std::uint32_t v = L; v < V; ++v) {
    const auto [a, b] = h.children[v - L];
    if (a >= v || b >= v || a == b || h.parent[a] != kNone || h.parent[b] != kNone)
      return makeError("view-dependent record has a broken vertex hierarchy");
    h.parent[a] = h.parent[b] = v;
    h.leafOf[v] = h.leafOf[a];
    if (h.error[v] < h.error[a] || h.error[v] < h.error[b])
      return makeError("view-dependent record has an error below a child's");
  }
  // Wedges and faces.
  o.leafWedgeStart.assign(L + 1, 0);
  for (std::uint32_t w = 0; w < W; ++w) {
    if (o.wedgeLeaf[w] >= L || (w > 0 && o.wedgeLeaf[w] < o.wedgeLeaf[w - 1]) ||
        o.wedgeChart[w] >= W)
      return makeError("view-dependent record has a broken wedge");
    ++o.leafWedgeStart[o.wedgeLeaf[w] + 1];
  }
  for (std::uint32_t l = 0; l < L; ++l) {
    if (o.leafWedgeStart[l + 1] == 0) return makeError("view-dependent record has a bare leaf");
    o.leafWedgeStart[l + 1] += o.leafWedgeStart[l];
  }
  h.faces.resize(F);
  for (std::uint32_t t = 0; t < F; ++t) {
    for (int i = 0; i < 3; ++i) {
      if (o.faceWedges[t][i] >= W) return makeError("view-dependent record has a broken face");
      h.faces[t][i] = o.wedgeLeaf[o.faceWedges[t][i]];
    }
    const auto& f = h.faces[t];
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2])
      return makeError("view-dependent record has a face with a repeated corner");
  }
  // Stored neighbourhoods: each corner the face's leaf there or an ancestor of it.
  if (h.neighbourhoodStart[0] != 0 || h.neighbourhoodStart[I] != S)
    return makeError("view-dependent record has broken neighbourhoods");
  for (std::uint64_t k = 0; k < I; ++k)
    if (h.neighbourhoodStart[k + 1] < h.neighbourhoodStart[k])
      return makeError("view-dependent record has broken neighbourhoods");
  std::vector<std::uint32_t> first, last;
  h.leafRanges(first, last);
  for (const vdr::StoredFace& s : h.storedFaces) {
    if (s.face >= F) return makeError("view-dependent record has a broken neighbourhood face");
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t c = s.corners[i], l = h.faces[s.face][i];
      if (c >= V || first[c] > first[l] || last[l] > last[c])
        return makeError("view-dependent record has a broken neighbourhood face");
    }
  }
  // Clusters: a tree rooted at 0, children naming their parent, counts matching.
  std::vector<std::uint32_t> count(K, 0);
  for (std::uint32_t c : o.clusters.clusterOf) {
    if (c >= K) return makeError("view-dependent record has a vertex in no cluster");
    ++count[c];
  }
  for (std::uint32_t c = 0; c < K; ++c) {
    const vdr::Cluster& k = o.clusters.clusters[c];
    const bool rootOk = c == 0 ? k.parent == kNone
                               : k.parent < c && (o.clusters.clusters[k.parent].children[0] == c ||
                                                  o.clusters.clusters[k.parent].children[1] == c);
    if (!rootOk || count[c] != k.vertexCount || !std::isfinite(k.minError) ||
        !std::isfinite(k.maxError) || k.minError > k.maxError ||
        k.depth != (c == 0 ? 0 : o.clusters.clusters[k.parent].depth + 1))
      return makeError("view-dependent record has a broken cluster");
    // Children made together (sec. 3.1's C_l and C_r): contiguous, the first one set.
    if ((k.children[0] == kNone && k.children[1] != kNone) ||
        (k.children[1] != kNone && k.children[1] != k.children[0] + 1))
      return makeError("view-dependent record has a broken cluster");
    for (std::uint32_t child : k.children)
      if (child != kNone && (child >= K || o.clusters.clusters[child].parent != c))
        return makeError("view-dependent record has a broken cluster");
  }
  return o;
}

StoredVdr storeVdrObject(const vdr::VdrObject& object) {
  const std::vector<std::byte> raw = encodeVdrObject(object);
  StoredVdr s;
  s.bytes = compressPayload(raw);
  s.entry.storedSize = s.bytes.size();
  s.entry.rawSize = raw.size();
  s.entry.checksum = crc32(s.bytes);
  s.entry.bounds = object.bounds();
  s.entry.faces = std::uint32_t(object.hierarchy.faces.size());
  s.entry.vertices = object.hierarchy.vertexCount();
  s.entry.clusters = std::uint32_t(object.clusters.clusters.size());
  return s;
}

std::vector<std::byte> encodeVdrIndex(std::span<const VdrEntry> entries,
                                      std::uint64_t indexOffset) {
  store::ByteWriter w;
  w.putBytes(kVdrIndexMagic, 8);
  w.put(kVdrIndexVersion);
  w.put(std::uint32_t(entries.size()));
  for (const VdrEntry& e : entries) {
    w.put(e.rootNode);
    w.put(e.offset);
    w.put(e.storedSize);
    w.put(e.rawSize);
    w.put(e.checksum);
    w.put(e.bounds.min);
    w.put(e.bounds.max);
    w.put(e.faces);
    w.put(e.vertices);
    w.put(e.clusters);
  }
  w.put(store::fnv1a64(w.bytes));
  const std::uint64_t size = w.bytes.size();
  w.put(indexOffset);
  w.put(size);
  w.putBytes(kVdrTrailerMagic, 8);
  return std::move(w.bytes);
}

Result<std::vector<VdrEntry>> decodeVdrIndex(std::span<const std::byte> index,
                                             std::uint64_t indexOffset, std::uint32_t nodeCount) {
  store::ByteReader r(index);
  char magic[8] = {};
  std::uint32_t version = 0, n = 0;
  if (!r.getBytes(magic, 8) || !r.get(version) || !r.get(n))
    return makeError("vdr.bin: index truncated");
  if (std::memcmp(magic, kVdrIndexMagic, 8) != 0) return makeError("vdr.bin: bad index magic");
  if (version != kVdrIndexVersion)
    return makeError("vdr.bin: index version " + std::to_string(version) +
                     " is not supported (rebuild the store with --vdr)");
  if (16 + std::uint64_t(n) * kVdrEntryBytes + 8 != index.size())
    return makeError("vdr.bin: index size does not match its object count");
  std::vector<VdrEntry> out(n);
  for (VdrEntry& e : out)
    if (!r.get(e.rootNode) || !r.get(e.offset) || !r.get(e.storedSize) || !r.get(e.rawSize) ||
        !r.get(e.checksum) || !r.get(e.bounds.min) || !r.get(e.bounds.max) || !r.get(e.faces) ||
        !r.get(e.vertices) || !r.get(e.clusters))
      return makeError("vdr.bin: index truncated");
  std::uint64_t sum = 0;
  if (!r.get(sum) || sum != store::fnv1a64(index.first(index.size() - 8)))
    return makeError("vdr.bin: index checksum mismatch (corrupt store)");
  for (const VdrEntry& e : out) {
    if (e.rootNode >= nodeCount) return makeError("vdr.bin: an object names no node of the store");
    if (e.offset > indexOffset || e.storedSize > indexOffset - e.offset || e.storedSize == 0)
      return makeError("vdr.bin: an object lies outside the file");
    if (!finite(&e.bounds.min.x, 3) || !finite(&e.bounds.max.x, 3))
      return makeError("vdr.bin: an object's box is not finite");
  }
  return out;
}

Result<std::vector<VdrEntry>> readVdrIndex(const std::filesystem::path& file,
                                           std::uint32_t nodeCount) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return makeError("cannot open " + file.string());
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  if (end < std::streamoff(kVdrTrailerBytes)) return makeError(file.string() + " is truncated");
  const auto size = std::uint64_t(end);
  std::byte trailer[kVdrTrailerBytes];
  in.seekg(std::streamoff(size - kVdrTrailerBytes));
  if (!in.read(reinterpret_cast<char*>(trailer), kVdrTrailerBytes))
    return makeError("cannot read " + file.string());
  std::uint64_t offset = 0, length = 0;
  std::memcpy(&offset, trailer, 8);
  std::memcpy(&length, trailer + 8, 8);
  if (std::memcmp(trailer + 16, kVdrTrailerMagic, 8) != 0)
    return makeError(file.string() + " is not a view-dependent section (or is truncated)");
  if (offset > size - kVdrTrailerBytes || length != size - kVdrTrailerBytes - offset)
    return makeError(file.string() + ": the index lies outside the file");
  std::vector<std::byte> index(length);
  in.seekg(std::streamoff(offset));
  if (!in.read(reinterpret_cast<char*>(index.data()), std::streamsize(length)))
    return makeError("cannot read " + file.string());
  return decodeVdrIndex(index, offset, nodeCount);
}

Result<vdr::VdrObject> readVdrObject(const std::filesystem::path& file, const VdrEntry& entry) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return makeError("cannot open " + file.string());
  std::vector<std::byte> stored(entry.storedSize);
  in.seekg(std::streamoff(entry.offset));
  if (!in.read(reinterpret_cast<char*>(stored.data()), std::streamsize(stored.size())))
    return makeError("cannot read " + file.string() + " (truncated?)");
  if (crc32(stored) != entry.checksum)
    return makeError(file.string() + ": an object's checksum does not match (corrupt store)");
  auto raw = inflatePayload(stored, entry.rawSize);
  if (!raw) return makeError(file.string() + ": " + raw.message());
  auto object = decodeVdrObject(*raw);
  if (!object) return makeError(file.string() + ": " + object.message());
  return object;
}

}  // namespace hlod
