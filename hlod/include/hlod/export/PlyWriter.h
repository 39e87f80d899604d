#pragma once
// Writes a Mesh as binary little-endian PLY that importModel reads back exactly: double x,y,z
// (no precision lost far from the origin), float normals and texture coordinates when present,
// and the MeshLab "comment TextureFile NAME" line naming a texture next to the file.
#include <filesystem>
#include <string>

#include "hlod/Mesh.h"
#include "hlod/Result.h"

namespace hlod {

// Texture coordinates are written in PLY convention (v up, i.e. 1 - v) and flipped back on read.
// Fails (without a partial file being left as success) on I/O errors or inconsistent arrays.
Status writePly(const std::filesystem::path& path, const Mesh& mesh,
                const std::string& textureFileName = "");

}  // namespace hlod
