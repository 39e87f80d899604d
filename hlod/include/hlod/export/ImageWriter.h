#pragma once
// Image files out: the rendered frames and the city's block textures.
#include <filesystem>

#include "hlod/Mesh.h"
#include "hlod/Result.h"

namespace hlod {

struct ImageWriteOptions {
  bool alpha = false;    // keep the alpha channel; frames are opaque and written as RGB
  bool fastPng = false;  // PNG at compression level 1 without row filters (noisy textures)
};

// Writes `image` (RGBA8, row 0 at the top) in the format the extension of `path` names (.png,
// .bmp, .jpg, .tif, .exr as half floats, ...). The file is encoded in memory and then written
// with every write, the flush and the close checked: a full disk or an unwritable file is an
// Error naming the file and the reason, never a silent success. A partly written regular file
// is removed again.
Status writeImageFile(const std::filesystem::path& path, const Image& image,
                      const ImageWriteOptions& options = {});

}  // namespace hlod
