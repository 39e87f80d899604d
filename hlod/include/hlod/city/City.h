#pragma once
// The procedural city: hlodr's embedded default scene.
//
// Modelled on the scanned Berkeley city of Lakhia (shared/seeds/lakhia-hlod.txt, Figs. 2 and 5):
// the city is split into blocks, each "one side of a city block": a row of building facades
// along a street, no two buildings alike, each block with its own texture. Blocks are laid out on
// a street grid: grid cell k (square shells from the origin, so block i sits at the same place
// whatever the block count) has four blocks, one per side, each facing its street.
//
// Frame: city coordinates in metres, X east, Y north, Z up, ground at z = 0: the east-north-up
// frame (hlod/geodesy/Geodesy.h, WGS84) at the city's origin, the south-west corner of the first
// grid cell, which for the procedural city is kCityOriginLat/kCityOriginLon at height 0.
//
// Generation is deterministic: the same (seed, index) gives the same block, bit for bit, on
// every platform that has the same floating point (own splitmix64 PRNG, no <random>
// distributions).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "hlod/geodesy/Geodesy.h"

namespace hlod {

// 64 blocks (16 grid cells, 4x4) of ~40k triangles each: about 2.5 million triangles.
inline constexpr int kDefaultCityBlocks = 64;
inline constexpr int kMaxCityBlocks = 100000;
inline constexpr std::uint64_t kDefaultCitySeed = 1;
// Texels per side of a block's texture (~6-8 texels a metre of facade). Painting and PNG encoding
// are most of writeCity's time, and grow with the texels: a larger default would slow the city
// down more than it shows.
inline constexpr int kDefaultCityTextureSize = 512;
// Geographic anchor of the city origin (Berkeley, as the paper's scanned city).
inline constexpr double kCityOriginLat = 37.87;
inline constexpr double kCityOriginLon = -122.27;

struct CityOptions {
  int blocks = kDefaultCityBlocks;  // 1..kMaxCityBlocks
  std::uint64_t seed = kDefaultCitySeed;
  int textureSize = kDefaultCityTextureSize;  // 64..4096
  bool textures = true;  // false: generateBlock skips painting (geometry only, for counts)
};

// Block `index` (0-based, any index >= 0: the layout does not depend on options.blocks) in city
// coordinates, with per-vertex normals, texture coordinates and its RGBA texture attached
// (unless options.textures is false). The geometry does not depend on options.textures.
Mesh generateBlock(const CityOptions& options, int index);

// File name stem of block `index`: "block_0000".
std::string cityBlockName(int index);

// The geodetic position of a point in the procedural city's coordinates: the ENU frame at
// (kCityOriginLat, kCityOriginLon, 0).
LatLon cityToLatLon(const glm::dvec3& cityPosition);

struct CityProgress {
  int blocksDone = 0;
  int blocksTotal = 0;
  std::size_t triangles = 0;  // written so far
  double seconds = 0.0;       // since the start
};
using CityProgressFn = std::function<void(const CityProgress&)>;

// About how many bytes writeCity writes for `options`, erring high (a refusal must not come too
// late): per block 2.4 MB of PLY and 1.3 bytes of PNG a texel, a little above what the default
// city's blocks take, plus the manifest.
std::uint64_t estimateCityBytes(const CityOptions& options);

// Writes dir/city.json and, per block, dir/block_NNNN.ply (hlod::writePly, binary, double
// positions) and dir/block_NNNN.png. Creates dir if needed. Refuses, before writing a block,
// when estimateCityBytes is more than the disk holding dir has free. Streams: one worker per core
// (at most 8), each holding one block in memory at a time; progress is reported in block order from
// the calling thread. city.json is written last (via a temporary file), so a folder with city.json
// is complete.
Status writeCity(const std::filesystem::path& dir, const CityOptions& options,
                 const CityProgressFn& progress = {});

// How a block's mesh file gives its coordinates (the manifest's block "frame").
enum class BlockFrame {
  City,    // "city" (the default): metres in the city's frame, the ENU frame at its origin
  Anchor,  // "anchor": metres in the ENU frame at the block's own anchor
};

struct CityBlockInfo {
  std::string name;
  std::filesystem::path mesh;     // dir / the manifest's relative path
  std::filesystem::path texture;  // empty when the block has none
  std::size_t triangles = 0;
  Aabb bounds;  // in city coordinates (the manifest's bounds, moved from the anchor's frame)
  // The geographic position of the block: the manifest's "anchor" (lat, lon, optional height),
  // or, when it has none, that of its bounds' centre. A BlockFrame::Anchor block needs one.
  LatLon anchor;
  BlockFrame frame = BlockFrame::City;
};

struct CityManifest {
  std::filesystem::path dir;
  std::uint64_t seed = 0;
  LatLon origin;  // of the city's frame ("origin": lat, lon, optional height)
  std::size_t triangles = 0;
  std::vector<CityBlockInfo> blocks;
};

// True when `dir` is a folder holding a city.json.
bool isCityFolder(const std::filesystem::path& dir);

// Reads and validates dir/city.json: an Error for malformed JSON, a wrong format/version, missing
// or mistyped fields, non-finite numbers, latitudes beyond +-90, longitudes beyond +-180, an
// unknown block frame, an "anchor" frame without an anchor, file paths that escape dir
// (absolute, "..") and block files that do not exist.
Result<CityManifest> readCityManifest(const std::filesystem::path& dir);

// Loads block i (through hlod::importModel) as one mesh named after the block, with its texture,
// in city coordinates: a BlockFrame::Anchor block's positions and normals are moved from its
// anchor's ENU frame into the city's (through ECEF, in double precision: exact across the
// antimeridian and at the poles).
Result<Mesh> loadCityBlock(const CityManifest& manifest, std::size_t i);

// Loads every block of the city folder: one mesh per block.
Result<Model> loadCity(const std::filesystem::path& dir);

}  // namespace hlod
