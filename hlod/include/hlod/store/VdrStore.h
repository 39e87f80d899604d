#pragma once
// The view-dependent section of a node store (`hlodr build --vdr`): vdr.bin beside skeleton.bin
// and payload.bin, one record per block (the block's mesh as a hlod::vdr::VdrObject: vertex
// hierarchy, stored neighbourhoods, cluster hierarchy, wedges, texture), then an index.
// Formats (little-endian; each versioned; every count, size and index checked on decoding):
//   record (stored raw-DEFLATEd, CRC-32 of the stored bytes in the index): u32 "HLVD",
//     u32 version, u32 flags (1: texture coordinates, 2: one-sided, 4: texture), u32 leaves L,
//     vertices V (>= L), faces F, wedges W (>= L), stored faces S, clusters K, texture width,
//     height; f64 centre[3], f32 baseColor[4], f64 errorFloor; f32 leaf positions[3 L] (relative
//     to the centre); u32 children[2 (V - L)] (kept, removed: each below its parent, each vertex
//     the child of one parent at most); f32 error[V] (finite, >= 0, never below a child's);
//     f32 radius[V] (finite, >= 0); u32 clusterOf[V] (< K); u32 neighbourhoodStart[V - L + 1]
//     (0, ascending, ends at S); S x {u32 face (< F), corners[3]: each the vertex or an
//     ancestor of the face's leaf there}; f32 wedge normals[3 W]; f32 wedge texCoords[2 W] (if
//     flagged); u32 wedge leaf[W] (ascending, every leaf at least once); u32 wedge chart[W] (<
//     W); u32 face wedges[3 F] (< W, three distinct leaves); K x {u32 parent (kNone for
//     cluster 0 only, else below the cluster), child0, child1 (kNone or clusters naming it their
//     parent), vertexCount, depth; f32 minError, maxError}; u8 RGBA pixels[4 w h] (if flagged).
//   index, after the records: "HLODVDRI", u32 version, u32 object count N; N x {u32 root node
//     (the block's hlod_0 node in the skeleton), u64 offset, u64 stored size, u64 raw size, u32
//     CRC-32, f64 box min[3], max[3], u32 faces, vertices, clusters}; u64 FNV-1a of the index
//     bytes before it. The file ends with u64 index offset, u64 index size and "HLODVDR0".
// A truncated or corrupted section is an Error when opened or decoded, never a crash.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "hlod/vdr/VdrObject.h"

namespace hlod {

constexpr std::uint32_t kVdrRecordVersion = 1;
constexpr std::uint32_t kVdrIndexVersion = 1;

// What the index says of one record.
struct VdrEntry {
  std::uint32_t rootNode = 0;
  std::uint64_t offset = 0;
  std::uint64_t storedSize = 0;
  std::uint64_t rawSize = 0;
  std::uint32_t checksum = 0;
  Aabb bounds;
  std::uint32_t faces = 0, vertices = 0, clusters = 0;
};

// A record as the file stores it: deflated, with its index entry (offset filled on append).
struct StoredVdr {
  std::vector<std::byte> bytes;
  VdrEntry entry;
};

std::vector<std::byte> encodeVdrObject(const vdr::VdrObject& object);
// Strict decoding (see the format); the hierarchy's world positions are the centre plus the
// stored floats.
Result<vdr::VdrObject> decodeVdrObject(std::span<const std::byte> bytes);
// encodeVdrObject deflated, with the entry's sizes, checksum, box and counts (rootNode unset).
StoredVdr storeVdrObject(const vdr::VdrObject& object);

// The index and trailer that end vdr.bin, for entries whose offsets are set; indexOffset is
// where the index starts (the bytes of the records before it).
std::vector<std::byte> encodeVdrIndex(std::span<const VdrEntry> entries, std::uint64_t indexOffset);
// The index's bytes (without the trailer), found at indexOffset: every record must lie before
// it, and every root node be below nodeCount.
Result<std::vector<VdrEntry>> decodeVdrIndex(std::span<const std::byte> index,
                                             std::uint64_t indexOffset, std::uint32_t nodeCount);
// The index of a vdr.bin file, through its trailer.
Result<std::vector<VdrEntry>> readVdrIndex(const std::filesystem::path& file,
                                           std::uint32_t nodeCount);

// Reads one record of a vdr.bin: the stored bytes, checked and decoded.
Result<vdr::VdrObject> readVdrObject(const std::filesystem::path& file, const VdrEntry& entry);

}  // namespace hlod
