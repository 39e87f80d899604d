#pragma once
// A node store as an OGC 3D Tiles 1.1 tileset (OGC 22-025r4; CesiumGS/3d-tiles, specification/):
// DIR/tileset.json and one binary glTF per node (DIR/content/nN.glb, hlod/tiles/Glb.h), so that
// CesiumJS, cesium-native and 3DTilesRendererJS stream what hlodr built.
//
// The tile tree is the store's node tree: refine REPLACE (a node is drawn instead of its
// children, as hlodr draws it), one tile per node with its node's content. A store with several
// roots (blocks without cell nodes) gets a root tile without content above them.
//
// geometricError (3D Tiles: "the error, in meters, introduced if this tile is rendered and its
// children are not") is the node's simplification error, the geometricError hlodr's SSE selector
// projects: a viewer's screen-space error is geometricError * height / (2 tan(fovy / 2) d), the
// same formula at its distance d to the tile's box (SseSelector::screenSpaceError), so a viewer
// at 16 px refines where hlodr's `sse` selector at 16 px refines. Leaves get 0 (there is nothing
// finer), and a tile's error is at least its children's (errors never grow downwards). The
// tileset's and a synthetic root's error is the model's diagonal: refined whenever the model
// spans more than the SSE threshold, as hlodr always draws its roots.
//
// Frames (3D Tiles sec. "Transforms": glTF node transform, then y-up to z-up, then the tile
// transform). The tiles' frame is z up: the store's world turned so that its up axis is z (a
// permutation of the axes, exact). glTF content is y up: positions are the node's float
// offsets from its centre, permuted into glTF's axes, under a node whose translation is the
// centre (relative to centre: float offsets of a few metres, never ECEF-sized floats).
// A geo-referenced store (Skeleton::crs converted to east-north-up, a city folder, or a
// projected CRS hlodr can invert) gets a root transform from its east-north-up frame to ECEF
// (EPSG:4978), so viewers place it on the globe; a projected CRS by the linear map that fits its
// inverse projection at the model's centre.
//
// Bounding volumes are boxes (12 numbers: centre, then the x, y and z half-axes) holding every
// vertex of the tile's content as a viewer computes it (centre + float offset) and the node's box.
//
// Textures: a node's own texture is embedded in its GLB; a texture several nodes share in the
// store is written once (content/tex-K.png or .jpg) and referred to by each GLB's image URI.
//
// Extras: each tile's `extras.hlodr` keeps what a viewer does not need and hlodr does to read the
// tileset back as the store it came from: the node's number, block, level, cell flag, world
// centre and box, cost (eq. 1), static benefit (eq. 2), average normal (eq. 3), triangle counts,
// its own geometric error and the anchor of a block's root; the tileset's `extras.hlodr` the
// world's up axis and axis map, CRS, build parameters and facts.
//
// What does not survive: a node's progression (Parry's simplification arrays) has no glTF form;
// the tile holds the node's whole triangles (drawn whole, as `--params progressive=0` draws).
// Splats are no content (viewers would draw them besides the triangles): hlodr computes them
// again from the triangles on import. Cell nodes are tiles like any other node.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "hlod/Result.h"
#include "hlod/store/NodeStore.h"

namespace hlod::tiles {

struct TilesetExportOptions {
  // Textures as JPEG at this quality (1..100), else PNG (lossless, the default: an export read
  // back draws exactly what the store drew).
  int jpegQuality = 0;
  // Checked before each node: once true, the export stops with an Error ("cancelled") and
  // leaves nothing behind (a server's export job; the command line has none).
  const std::atomic<bool>* cancel = nullptr;
};

struct TilesetExportReport {
  std::size_t tiles = 0;           // tiles in tileset.json (nodes, and a synthetic root)
  std::size_t contents = 0;        // .glb files
  std::size_t sharedTextures = 0;  // textures written once for several nodes
  std::uint64_t bytes = 0;         // all files written
  bool geoReferenced = false;      // placed on the globe (a root transform to ECEF)
  std::string frame;               // how the world was placed, for the user
};

using TilesetExportProgress = std::function<void(std::size_t done, std::size_t total)>;

// Ok when dir does not exist, is empty, or holds an earlier export (tileset.json written by
// hlodr and its content/ folder): the folders an export may replace.
Status checkReplaceableExport(const std::filesystem::path& dir);

// Writes the tileset into a temporary folder beside dir and renames it into place, so a failed
// export leaves no half tileset (and an earlier export stays until the new one is complete).
Result<TilesetExportReport> exportTileset(const NodeStore& store, const std::filesystem::path& dir,
                                          const TilesetExportOptions& options = {},
                                          const TilesetExportProgress& progress = {});

}  // namespace hlod::tiles
