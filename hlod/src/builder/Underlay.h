#pragma once
// A cell node's underlay (builder/CellNodes.h): a quad under the cell in the colour of its lowest
// ground, which shows where the simplification opened a street (ground, not sky, through the
// gap). Private to the builder.
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"
#include "hlod/UpAxis.h"

namespace hlod {

// Below this fraction of its horizontal size under its lowest point, a cell's underlay.
constexpr double kUnderlayDepth = 0.01;
// Appends the underlay of a cell of `box` to its simplified mesh (texture coordinates: colour
// indices, as mergeCellChildren's): a quad facing up over the box's footprint, kUnderlayDepth
// of its larger horizontal side below its bottom, in the area-weighted colour of `input`'s
// triangles facing up within a metre of the bottom (appended to colours). Nothing without them.
void addUnderlay(Mesh& mesh, const Mesh& input, std::vector<glm::vec4>& colours, const Aabb& box,
                 UpAxis up);

}  // namespace hlod
