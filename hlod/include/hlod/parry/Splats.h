#pragma once
// A node's splats (Parry et al. sec. 3 and 5: "Without connectivity information, these node
// properties can be used for fast, multiresolution splat rendering [Rus00]"): a cut through the
// bounding-sphere hierarchy of the vertices its triangles use (one tree, as QSplat's), each
// splat with its sphere's centre, radius and normal, and the texture coordinate of the vertex
// nearest its centre (averages of texture coordinates would cross atlas regions).
#include <cstddef>
#include <vector>

#include "hlod/Mesh.h"

namespace hlod {

// Enough to cover a node drawn a few pixels wide (the only size it is drawn as splats at).
constexpr std::size_t kSplatsPerNode = 64;

std::vector<Splat> makeSplats(const LocalMesh& mesh, std::size_t count = kSplatsPerNode);

}  // namespace hlod
