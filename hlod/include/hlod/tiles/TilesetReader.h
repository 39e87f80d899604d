#pragma once
// The tile tree of a 3D Tiles tileset, 1.0 or 1.1, as its JSON files describe it: every tile with
// its computed transform, geometric error, refinement and content files, external tilesets and
// implicit tiling (QUADTREE and OCTREE subtrees) expanded into explicit tiles. Content is not read
// here beyond its first bytes (to tell an external tileset from a model); TilesetImport.h turns
// the tree into a node store.
//
// 3D Tiles 1.1 (OGC 22-025r4; CesiumGS/3d-tiles specification/README.adoc):
// - tileset.schema.json: asset (version required), geometricError, root; tile.schema.json:
//   boundingVolume and geometricError required, refine required at the root and inherited,
//   transform (16 numbers, column-major) composed down the tree ("post-multiplying a child's
//   transform with its parent's"), content or contents (not both), children.
// - External tilesets (sec. "External tilesets"): a tile whose content is a tileset JSON; the
//   external root is its only child, under both tiles' transforms. Cycles are refused.
// - Implicit tiling (ImplicitTiling/README.adoc): the children of an implicit root tile follow
//   from its subtrees' availability; each child's geometricError is half its parent's, refine and
//   transform are the root's, content URIs come from the template.
// - Content URIs are relative to the JSON file that names them; a query ("?v=2") or fragment is
//   dropped and %XX decoded. Every file is read from inside the first tileset's folder only
//   (insideFolder): an absolute path, a ".." that climbs out, a link leading out or a remote URL
//   is refused by name.
// Errors name the tile: "tileset.json: tile root/0/1: ..." (child indices from the root; for an
// external or implicit tile, the JSON file or the subtree coordinates it comes from).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "hlod/Result.h"
#include "hlod/tiles/Glb.h"

namespace hlod::tiles {

// Bounds of what a tileset may expand to; past them the read is an Error naming the tile.
struct TilesetLimits {
  std::uint64_t maxTiles = 1'000'000;         // tiles in all, implicit ones included
  std::uint32_t maxDepth = 64;                // tile levels, external tilesets included
  std::uint32_t maxExternalNesting = 32;      // tilesets within tilesets
  std::uint64_t maxJsonBytes = 256ull << 20;  // one tileset JSON or subtree file
  std::uint32_t maxImplicitLevels = 30;       // availableLevels of an implicit tree
};

struct TileRecord {
  static constexpr std::uint32_t kNone = 0xffffffffu;
  std::uint32_t parent = kNone;
  std::vector<std::uint32_t> children;
  std::string name;             // for messages: "tileset.json: tile root/0/1"
  std::uint32_t depth = 0;      // 0 at the root
  glm::dmat4 transform{1.0};    // the tile's frame to the tileset's frame (all transforms)
  AxisMap contentUp;            // glTF content's frame to the tile's frame (y up to z up)
  double geometricError = 0.0;  // in the tileset's frame (scaled by the transforms)
  bool add = false;             // refine ADD (else REPLACE)
  std::vector<std::filesystem::path> contents;  // resolved files of models (no tilesets)
  // The bounding volume's centre in the tileset's frame, and whether it is a region (EPSG:4979,
  // which says the tileset's frame is earth-centred).
  glm::dvec3 volumeCentre{0.0};
  bool region = false;
  double regionMinHeight = 0.0;
  nlohmann::json hlodr;  // extras.hlodr of the tile (an hlodr export), or null
};

struct TilesetTree {
  std::filesystem::path folder;   // the first tileset's folder: every file comes from inside it
  std::string version;            // asset.version of the first tileset
  std::vector<TileRecord> tiles;  // tiles[0] is the root; parents before their children
  nlohmann::json hlodr;           // extras.hlodr of the first tileset (an hlodr export), or null
  std::vector<std::string> warnings;  // what was read but not used (viewerRequestVolume, ...)
};

// True when the file is a 3D Tiles tileset JSON (an object with "asset" and "root").
bool isTilesetFile(const std::filesystem::path& path);

Result<TilesetTree> readTilesetTree(const std::filesystem::path& tilesetJson,
                                    const TilesetLimits& limits = {});

}  // namespace hlod::tiles
