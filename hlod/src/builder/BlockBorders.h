#pragma once
// Where a piece's vertices meet the rest of its block, other blocks, and the block's sides: the
// lock flags a simplifier gets (Simplifier.h), so that neighbouring nodes meet on the same
// vertices at every level. Private to the builder.
#include <cstdint>
#include <span>
#include <vector>

#include "hlod/builder/HlodBuilder.h"

namespace hlod {

// Where the vertices of a welded block stand: one id per distinct position, how many triangle
// corners of the whole block each position has, and whether another block shares it. A piece's
// vertex with fewer corners in the piece than in the block lies on the piece's border.
struct BlockBorders {
  std::vector<std::uint32_t> positionOf;  // per block vertex
  std::vector<std::uint32_t> corners;     // per position
  std::vector<std::uint8_t> seam;         // per position
  std::vector<std::uint32_t> scratch;     // per position, zero between calls of lockBorder
};

BlockBorders blockBorders(const Mesh& block, std::span<const glm::dvec3> seam);

// One flag per vertex of the piece (origin: its block vertices): kVertexLocked where the rest of
// the block or another block has the same position.
std::vector<std::uint8_t> lockBorder(const Mesh& piece, const std::vector<std::uint32_t>& origin,
                                     BlockBorders& b);

// Adds the outline flags of the piece's vertices on the block's sides: kVertexOnOutline on a
// straight run of the open border there (or off the border: a kerb face lying in the side),
// kVertexLocked at a corner of it, where a collapse would cut the corner off and open a crack.
void markOutline(const Mesh& piece, const std::vector<std::uint32_t>& origin, BlockBorders& b,
                 std::span<const CutPlane> sides, std::vector<std::uint8_t>& flags);

// The error a node with simplification factor s may have: the spacing of its level's triangles
// spread evenly over the whole block (the level holds blockTriangles / s of them). A piece's own
// target does not bound it: a courtyard's paving, three large triangles in a piece, has a
// target of one, and the collapse that meets it drops 37 m of paving.
double errorLimit(double blockArea, std::size_t blockTriangles, double s);

}  // namespace hlod
