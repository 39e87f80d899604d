#pragma once
// A cell node's texture, baked from its children (private to the builder): the simplified cell is
// cut into charts, packed into one atlas, and each texel takes the colour of the children's
// textured surface where the cell's surface stands for it, as HLOD tools bake merged meshes
// (Unreal's merged actors with baked materials, Simplygon's texture casting). Without it a cell
// is drawn in flat colours, and a city seen from the air loses its windows and facades.
#include <cstdint>
#include <span>

#include "hlod/Mesh.h"
#include "hlod/UpAxis.h"

namespace hlod {

struct CellAtlasOptions {
  UpAxis up = UpAxis::Z;
  double texelSize = 1.0;  // world units a texel spans (raised when the atlas would pass maxSide)
  int maxSide = 1024;      // the atlas's largest side, texels
  // How far a texel's cast starts outside the cell's surface and how deep it goes below it:
  // about the cell's geometric error (the children's surface lies within it of the cell's).
  double castDepth = 1.0;
};

struct CellAtlasStats {
  std::size_t charts = 0;
  std::size_t texels = 0;  // texels inside charts
  std::size_t missed = 0;  // of them, no child surface on their cast: the nearest one's colour
  double texelSize = 0.0;  // as used
};

// Charts: the triangles facing up or down (|normal . up| >= 0.5) map top-down onto one chart, the
// cell's plan (streets, roofs, the boxes' roofs, the underlay, which gets the colour of the ground
// above it); the others are grouped into planar patches (triangles sharing an edge whose normals
// are within 25 degrees of the patch's first), each projected on its own plane: a box's wall is
// one patch. Charts are packed on shelves, tallest first, with a gutter of two texels that is then
// filled from the chart's edge (mipmaps and bilinear filtering read across it).
// A texel of the plan takes the first child surface seen looking down on it from above the cell;
// a texel of a patch the first seen looking at the patch from castDepth in front of it, at most
// 2 castDepth deep; where no surface is met, the nearest child surface's colour. A child's colour
// is its texture's (bilinear, wrapping) times its base colour, or its base colour without one.
//
// mesh: world positions, three vertices per triangle (flat: its vertices belong to it alone, as
// flatColoured leaves them); gets texture coordinates into the atlas, which becomes its texture.
// children: world position = centre + position. Children without triangles are ignored; with no
// child triangle at all the mesh keeps its texture.
CellAtlasStats bakeCellAtlas(Mesh& mesh, std::span<const LocalMesh> children,
                             const CellAtlasOptions& options);

// The world size of the children's texels: the square root of their textured surface's area over
// their textures' texels (0 when none is textured). A cell whose error is k times its
// children's is drawn from k times as far, so texels k times as large look as theirs do: the
// atlas is as sharp on screen at the cell's switch distance as the children's at theirs.
double texelSizeOf(std::span<const LocalMesh> children);

}  // namespace hlod
