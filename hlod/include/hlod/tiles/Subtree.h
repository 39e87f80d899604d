#pragma once
// Implicit tiling's subtrees (3D Tiles 1.1, ImplicitTiling/README.adoc and AVAILABILITY.adoc;
// schema Subtree/subtree.schema.json, availability.schema.json): which tiles of a fixed-depth
// piece of a quadtree or octree exist, which have content, and which child subtrees follow.
// A subtree file is JSON, or binary: magic "subt", version 1, u64 JSON byte length, u64 binary
// byte length, then the JSON and the binary chunk (the internal buffer). Availability is a
// constant, or a bitstream in a buffer view: bit i is bit (i % 8) of byte i / 8 (the booleans of
// the 3D Metadata specification); tiles are ordered by level, then by Morton index within it.
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "hlod/Result.h"

namespace hlod::tiles {

struct Availability {
  bool constant = true;
  bool value = false;              // the constant
  std::vector<std::uint8_t> bits;  // the bitstream, at least ceil(length / 8) bytes
  std::uint64_t length = 0;        // elements

  bool at(std::uint64_t i) const {
    if (i >= length) return false;
    return constant ? value : ((bits[i / 8] >> (i % 8)) & 1u) != 0;
  }
};

struct Subtree {
  Availability tiles;                  // (N^levels - 1) / (N - 1) elements
  std::vector<Availability> contents;  // one per content of the implicit root
  Availability childSubtrees;          // N^levels elements
};

// The bytes of a buffer a subtree refers to by URI (relative to the subtree file); the caller
// resolves it inside the tileset's folder.
using SubtreeBufferLoader = std::function<Result<std::string>(const std::string& uri)>;

// Subtrees of branching 4 (quadtree) or 8 (octree) and `levels` levels: N^levels must not exceed
// 2^32 (quadtrees up to 16 levels, octrees up to 10), and every bitstream must hold its elements.
Result<Subtree> parseSubtree(std::string_view bytes, unsigned branching, unsigned levels,
                             const SubtreeBufferLoader& loadBuffer);

// The Morton index of (x, y) or (x, y, z): the coordinates' bits interleaved, x lowest
// (AVAILABILITY.adoc: interleaveBits(0b11, 0b00) = 0b0101).
std::uint64_t mortonIndex(std::uint32_t x, std::uint32_t y);
std::uint64_t mortonIndex(std::uint32_t x, std::uint32_t y, std::uint32_t z);

// A template URI with {level}, {x}, {y} and {z} replaced (ImplicitTiling sec. "Template URIs").
std::string expandTemplate(std::string_view uri, std::uint32_t level, std::uint32_t x,
                           std::uint32_t y, std::uint32_t z);

}  // namespace hlod::tiles
