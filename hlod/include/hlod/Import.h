#pragma once
// Mesh import: OBJ (+MTL, textures), PLY (ascii/binary, float/double), OFF, STL (ascii/binary),
// glTF 2.0 (.gltf/.glb, base-colour textures). Every failure is an Error naming the file and the
// problem (truncated, bad index, NaN coordinate, empty, unknown format); never a crash.
#include <filesystem>

#include "hlod/Mesh.h"
#include "hlod/Result.h"

namespace hlod {

// True when the extension is one importModel understands.
bool isMeshFile(const std::filesystem::path& path);

// Loads a mesh file into a Model (one Mesh per material/primitive group).
Result<Model> importModel(const std::filesystem::path& path);

// Loads an image file (PNG, JPEG, ...) into RGBA8.
Result<Image> loadImage(const std::filesystem::path& path);

}  // namespace hlod
