#pragma once
// A 3D Tiles tileset (1.0 or 1.1) as a node store, its own hierarchy kept: `hlodr build
// TILESET.json -o STORE`. Each tile with content becomes a node holding its content's triangles
// (nothing is simplified again), its geometricError the tile's; cost (eq. 1), static benefit
// (eq. 2) and average normal (eq. 3) are computed per node as the builder computes them (Lakhia
// III-B), so every selector runs on it, budget-bound Lakhia included.
//
// Content: glb and glTF JSON (3D Tiles 1.1), b3dm with its feature and batch tables (1.0),
// cmpt holding them, each placed by the spec's order: glTF node transforms, y-up to z-up (or the
// asset's gltfUpAxis), RTC_CENTER (b3dm) or CESIUM_RTC, then the tile transforms. i3dm and pnts
// hold no triangles hlodr draws: skipped with a warning. A tile's materials go into one texture
// (MergeMaterials.h). Single-sided glTF materials are drawn one-sided, as viewers draw them.
//
// The tree (3D Tiles refinement, "Refinement"):
// - a tile without content is no node: its children take its place (viewers refine past empty
//   tiles; hlodr has no empty nodes), and a root without content leaves its children as the
//   store's roots, one block each;
// - REPLACE is hlodr's own rule;
// - ADD (children draw in addition to their parent) becomes REPLACE by handing the parent's
//   triangles down: each child holds its own content and the parent's triangles nearest its
//   bounding volume's centre, so the leaves hold every tile's content once and a parent is drawn
//   alone or all its triangles are drawn by its children.
//
// The world (hlodr's frame): an earth-centred tileset (a region bounding volume, or a root within
// 6,000-7,000 km of the earth's centre) is converted, in double precision, into the east-north-up
// frame at its root's centre (up z; the store's CRS says where, as a geocentric CityJSON's does),
// so that cameras and paths stand on the ground; any other tileset keeps its own coordinates, and
// stands on the axis its surfaces face on average (3D Tiles says z, but y-up data marked
// gltfUpAxis Z, as NASA's Mars tileset, stands on y), unless `up` says.
//
// A tileset hlodr exported (hlod/tiles/TilesetExport.h) is read back as the store it came from:
// node numbers, blocks, levels, cell nodes, centres, boxes, measures and the quadtree's anchors
// from its extras, its world through the axis map it wrote (the root transform is its placement).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hlod/Result.h"
#include "hlod/UpAxis.h"
#include "hlod/store/Skeleton.h"
#include "hlod/tiles/TilesetReader.h"

namespace hlod::tiles {

struct TilesetImportOptions {
  double cTex = 0.6;         // c_tex of eq. 1
  std::optional<UpAxis> up;  // the store's up axis, whatever the tileset suggests
  TilesetLimits limits;
  // Content files larger than this are refused (an error naming the tile).
  std::uint64_t maxContentBytes = 1ull << 30;
};

struct TilesetImportReport {
  std::size_t tiles = 0;        // in the tileset, external and implicit ones included
  std::size_t contents = 0;     // content files read
  std::size_t nodes = 0;        // in the store
  std::size_t emptyTiles = 0;   // tiles without content (their children took their place)
  std::size_t addTiles = 0;     // tiles refined by ADD (their triangles handed down)
  std::uint64_t triangles = 0;  // in all nodes
  bool hlodrExport = false;     // read back as the store it came from
  std::string frame;            // how the world was chosen
  Skeleton skeleton;
  std::vector<std::string> warnings;
};

struct TilesetImportProgress {
  std::size_t tilesDone = 0, tileCount = 0;
};
using TilesetImportProgressFn = std::function<void(const TilesetImportProgress&)>;

// Reads the tileset and writes the store (through NodeStoreWriter: under a temporary name,
// renamed at the end; never over a folder that is not a store).
Result<TilesetImportReport> buildStoreFromTileset(const std::filesystem::path& tilesetJson,
                                                  const std::filesystem::path& storeDir,
                                                  const TilesetImportOptions& options = {},
                                                  const TilesetImportProgressFn& progress = {});

}  // namespace hlod::tiles
