#pragma once
// The node store on disk, NAME.hlod/ (a folder), written by the HLOD builder:
//   skeleton.bin  the Skeleton (every NodeInfo field), build parameters and a checksum; loaded
//   whole. payload.bin   the node payloads, one after another, each compressed with raw DEFLATE
//   (a third of the bytes to read on the default city), read on demand in chunks with pread.
//   vdr.bin (optional, `hlodr build --vdr`): the view-dependent section, one record per block
//   and an index (hlod/store/VdrStore.h); a store without it opens as before.
// Formats (little-endian; each versioned, every count and offset bounds-checked on read):
//   skeleton.bin: "HLODSKEL", u32 version, u32 0x01020304, build params, store facts, the model
//     frame (u32 up axis 0/1/2 for x/y/z, i32 EPSG code, u32 toEnu 0/1, f64 origin lat, lon,
//     height, u32 n, n bytes of printable ASCII CRS description, n <= kMaxCrsDescription),
//     node records, root list (ascending), the block quadtree (u32 domain 0/1/2, f64 rect minU,
//     minV, maxU, maxV, u32 depth, u32 cell count, u32 block count; per cell u32 level, x, y,
//     firstChild, childCount, firstBlock, blockCount, f64 box min[3], max[3]; per block u32
//     root, f64 anchor u, v), then a 64-bit FNV-1a of all preceding bytes. Version 4 added the
//     model frame, version 5 the texture section's offset (NodeInfo::textureOffset), version 6
//     the block quadtree and the progression's and the splats' counts (NodeInfo::minTri,
//     splatCount), version 7 cell nodes (NodeInfo::block kCellBlock, level 0; the quadtree's
//     blocks are the hlod_0 nodes below them); other versions are refused with "rebuild it" (stores
//     are derived data).
//   payload: u32 "HLPL", u32 version, u32 vertexCount, u32 indexCount, u32 flags (1: texCoords,
//     2: one-sided, 4: progression, 8: splats), u32 texWidth, u32 texHeight, f32 baseColor[4], f32
//     positions[3 vc] (relative to the node's centre), f32 normals[3 vc], f32 texCoords[2 vc] (if
//     flagged), u32 indices[ic], the progression if flagged (4; u32 combinations c > 0, u32
//     moves m > 0, u32 moves[2 m], u32 moveEnd[c], u32 increments[c]: Mesh::progression,
//     checked to be drawable), the
//     splats if flagged (8; u32 count s > 0, s x {f32 position[3], radius, normal[3],
//     texCoord[2]}: LocalMesh::splats), u8 RGBA pixels[4 w h]: NodeInfo::memoryBytes in all.
//     Version 3 added the progression and the splats; version 2 payloads are read too. payload.bin
//     holds it in two sections, each deflated on its own: the mesh (all but the pixels; CRC-32
//     NodeInfo::payloadChecksum) at payloadOffset, and the pixels (NodeInfo::textureSize stored
//     bytes, CRC-32 textureChecksum; absent without a texture) at textureOffset: right after the
//     mesh, or where another node of the same block and level stored the texture they share
//     (HlodBuilder.h says when). NodeInfo::payloadSize is the two sections' stored bytes. A
//     scene without textures reads only the mesh section.
// A truncated or corrupted store is an Error when opened or decoded, never a crash.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "hlod/store/NodeSource.h"
#include "hlod/store/VdrStore.h"

namespace hlod {

constexpr std::uint32_t kSkeletonFormatVersion = 7;
constexpr std::uint32_t kMaxCrsDescription = 256;  // bytes of ModelCrs::description kept
constexpr std::uint32_t kPayloadFormatVersion = 3;

// Facts about a whole store, beside the Skeleton.
struct StoreFacts {
  std::uint64_t inputTriangles = 0;
  std::uint32_t blockCount = 0;
  double buildSeconds = 0.0;
  std::uint64_t payloadBytes = 0;  // size of payload.bin
};

// CRC-32 (IEEE, as zlib) of bytes.
std::uint32_t crc32(std::span<const std::byte> bytes);

// Payload encoding of one node's mesh (see the format above).
std::vector<std::byte> encodePayload(const LocalMesh& mesh);
// Decodes with strict checks: exact size, counts against sizes, index < vertex count, finite
// values. centre is the node's centre (from the skeleton).
// pixels false: bytes end before the pixels (the mesh section), and the mesh has no texture.
Result<LocalMesh> decodePayloadBytes(std::span<const std::byte> bytes, const glm::dvec3& centre,
                                     bool pixels = true);
// The stored form of a payload in payload.bin: raw DEFLATE (libdeflate, level 1), and back.
// Inflating gives exactly memoryBytes or an Error.
std::vector<std::byte> compressPayload(std::span<const std::byte> raw);
Result<std::vector<std::byte>> inflatePayload(std::span<const std::byte> stored,
                                              std::uint64_t memoryBytes);

// A payload as payload.bin stores it: the deflated mesh and texture sections (the texture empty
// without one), and their inflated sizes. Thread-safe: the builder prepares blocks in parallel.
struct StoredPayload {
  std::vector<std::byte> mesh, texture;  // texture: empty for a node sharing another's
  std::uint64_t memoryBytes = 0;         // NodeInfo::memoryBytes
  std::uint64_t textureBytes = 0;        // NodeInfo::textureBytes
};
// withTexture false: the texture section is left out (the node shares one stored elsewhere), but
// memoryBytes and textureBytes count its pixels.
StoredPayload storePayload(const LocalMesh& mesh, bool withTexture = true);

// skeleton.bin encoding; decoding verifies the checksum, the tree's structure and the build
// parameters. A decoded skeleton guarantees what the rest of hlodr asserts: children
// [firstChild, firstChild + childCount) lie after their parent and inside nodes, each child's
// parent and level agree with it, roots are exactly the parentless nodes in ascending order
// (all cell nodes when there are cell nodes, which have level 0 and sit only below cell nodes),
// a quadtree (when there is one) holds every block's hlod_0 node exactly once, each in the leaf
// cell (at its depth) that quadCellAt gives for its anchor, each cell's box holding its blocks'
// hlod_0 boxes and its children's, children one quadrant each of their parent; payloads lie inside
// payload.bin, every double is finite, levelFactor is in [2, 64], c_tex in [0, 1], desiredTri
// at least 1, the build time finite and not negative, the up axis x, y or z, and the CRS
// description printable ASCII (the encoder replaces other bytes by '?' and cuts it to
// kMaxCrsDescription bytes).
std::vector<std::byte> encodeSkeleton(const Skeleton& skeleton, const StoreFacts& facts);
struct DecodedSkeleton {
  Skeleton skeleton;
  StoreFacts facts;
};
Result<DecodedSkeleton> decodeSkeleton(std::span<const std::byte> bytes);

class NodeStore final : public NodeSource {
 public:
  static Result<std::unique_ptr<NodeStore>> open(const std::filesystem::path& dir);
  ~NodeStore() override;
  NodeStore(const NodeStore&) = delete;
  NodeStore& operator=(const NodeStore&) = delete;

  const Skeleton& skeleton() const override { return skeleton_; }
  const StoreFacts& facts() const { return facts_; }
  // Thread-safe (pread).
  Status readPayloadChunk(std::uint32_t node, std::uint64_t offset,
                          std::span<std::byte> out) const override;
  // bytes: the whole stored payload, or only its mesh section (payloadSize - textureSize bytes,
  // a load without textures): then the mesh has no texture.
  Result<LocalMesh> decodePayload(std::uint32_t node,
                                  std::span<const std::byte> bytes) const override;
  // Reads and decodes a whole payload: the loader's two steps in one, for tools and tests.
  Result<LocalMesh> loadNode(std::uint32_t node) const;

  // The view-dependent section (vdr.bin, `hlodr build --vdr`; hlod/store/VdrStore.h): its
  // index, checked when the store is opened (empty without the section), and its objects.
  const std::vector<VdrEntry>& vdrEntries() const { return vdr_; }
  Result<vdr::VdrObject> loadVdrObject(std::size_t i) const;
  // The object decoded once and kept while the store is open: the sessions of one store share
  // it (it is read only). Thread-safe.
  Result<std::shared_ptr<const vdr::VdrObject>> sharedVdrObject(std::size_t i) const;

 private:
  NodeStore() = default;
  int fd_ = -1;
  Skeleton skeleton_;
  StoreFacts facts_;
  std::filesystem::path vdrFile_;
  std::vector<VdrEntry> vdr_;
  mutable std::mutex vdrMutex_;
  mutable std::vector<std::shared_ptr<const vdr::VdrObject>> vdrObjects_;
};

// Ok when dir does not exist, is empty, or is a node store (only skeleton.bin, payload.bin and
// vdr.bin, the skeleton with its magic): the folders a build may replace. Anything else is an Error
// that names what is in the way.
Status checkReplaceableStore(const std::filesystem::path& dir);

// Writes a store into a temporary folder beside the destination and renames it into place in
// finish(), so a failed build leaves no half store. Destroying an unfinished writer removes the
// temporary folder. create() and finish() refuse a destination that is not a store
// (checkReplaceableStore): a build never deletes what it did not write.
class NodeStoreWriter {
 public:
  static Result<std::unique_ptr<NodeStoreWriter>> create(const std::filesystem::path& dir);
  ~NodeStoreWriter();
  NodeStoreWriter(const NodeStoreWriter&) = delete;
  NodeStoreWriter& operator=(const NodeStoreWriter&) = delete;

  // Appends a node's payload; fills the node's payloadOffset, payloadSize, payloadChecksum and
  // its memory and texture sizes. appendPayload(m) is appendStored(storePayload(m)).
  Status appendPayload(const LocalMesh& mesh, NodeInfo& node);
  Status appendStored(const StoredPayload& payload, NodeInfo& node);
  // Appends payload's mesh section only; node's texture is the section `owner` (appended before)
  // stored. payload.memoryBytes counts the pixels, as the node holds them once decoded.
  Status appendSharingTexture(const StoredPayload& payload, const NodeInfo& owner, NodeInfo& node);
  // Makes what was appended so far readable by readBack.
  Status flush();
  // Reads and decodes the payload a node appended before the last flush() (what the skeleton's
  // node says). Thread-safe (pread), also while another thread appends.
  Result<LocalMesh> readBack(const NodeInfo& node) const;
  // Appends a view-dependent object (vdr.bin), the one of the block whose hlod_0 node is
  // rootNode; finish() writes the section's index after the last.
  Status appendVdr(StoredVdr&& object, std::uint32_t rootNode);
  // Writes skeleton.bin, flushes, and renames the folder to its destination (replacing an
  // existing store there).
  Status finish(const Skeleton& skeleton, StoreFacts facts);
  std::uint64_t payloadBytes() const { return payloadBytes_; }

 private:
  NodeStoreWriter() = default;
  std::filesystem::path dir_, tmp_;
  std::FILE* payload_ = nullptr;
  std::uint64_t payloadBytes_ = 0;
  std::FILE* vdr_ = nullptr;  // opened by the first appendVdr
  std::uint64_t vdrBytes_ = 0;
  std::vector<VdrEntry> vdrEntries_;
  bool finished_ = false;
};

}  // namespace hlod
