#pragma once
// A tile's content as one node mesh. A node store's node has one base colour and one texture
// (LocalMesh), while a tile's glTF may hold several primitives with their own materials. Meshes
// of one material are joined as they are; otherwise the materials go into one atlas texture:
// each texture (times its base colour, as glTF multiplies them) in a block of its own, and each
// untextured colour as a small block of that colour, with texture coordinates moved into their
// block. A block has a gutter of repeated edge texels so that filtering and the first mipmap
// levels do not blend neighbours. Texture coordinates outside [0, 1] (repeating textures) cannot
// repeat inside an atlas: they are wrapped per vertex, which stretches a triangle across the
// seam; such meshes are counted in the result.
#include <cstddef>
#include <span>

#include "hlod/Mesh.h"

namespace hlod::tiles {

struct MergedMesh {
  Mesh mesh;
  std::size_t atlasBlocks = 0;    // 0: the meshes shared one material, no atlas was made
  std::size_t wrappedMeshes = 0;  // textured meshes whose coordinates left [0, 1]
};

// Joins meshes (world coordinates); an empty span gives an empty mesh. Normals missing on some
// meshes are computed for those; the result is one-sided only when every mesh is.
MergedMesh mergeMaterials(std::span<const Mesh> meshes);

}  // namespace hlod::tiles
