#pragma once
// A cell node's flat colours (builder/CellNodes.h): its children merged into one mesh whose
// vertices carry colour indices, and the simplified mesh drawn from a palette texture, one flat
// colour per triangle. Private to the builder.
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"

namespace hlod {

// A cell is drawn in flat colours: a texture atlas of its children would not survive the
// simplification, whose triangles join vertices of different children (and of different
// children's atlases). mergeCellChildren gives the children as one world-space mesh whose
// texture coordinates hold, in x, an index into `colours`: each vertex's colour, the mean of its
// triangles' colours over their texture footprints (weighted by area) times its base colour.
// Vertices of one position and one colour weld; the simplifier keeps copies of input vertices,
// so the index survives it.
struct ColouredMesh {
  Mesh mesh;
  std::vector<glm::vec4> colours;
};
ColouredMesh mergeCellChildren(std::span<const LocalMesh> children);

// The simplified mesh in flat colours: each triangle the mean of its corners' colours, from a
// palette texture of one texel per distinct colour, all three corners of a triangle at its
// texel's centre (equal coordinates: the sampler stays at the base level, so no mipmap blends
// neighbouring colours), and flat shaded (three vertices per triangle, its face's normal). With
// smoothCos below 1, a corner keeps its own normal where that is within acos(smoothCos) of its
// face's (an object HLOD's pipes and tanks stay round).
Mesh flatColoured(const Mesh& simplified, std::span<const glm::vec4> colours,
                  float smoothCos = 1.0f);

// Keeps one of triangles with the same three vertices in the same turn: children that repeat
// their triangles (a pile of copies of one quad, which nothing can simplify) would otherwise hand
// the shape guard a pile whose every triangle is every query's nearest.
void dropRepeatedTriangles(Mesh& mesh);

}  // namespace hlod
