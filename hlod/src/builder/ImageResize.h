#pragma once
// Box-filter resize of an RGBA8 image: each output pixel the mean of the source pixels under it
// (OpenImageIO ImageBufAlgo::resize, "box" filter one destination pixel wide). The builder's
// textures shrink with their nodes' simplification (TextureCrop.h). Private to the builder.
#include "hlod/Mesh.h"

namespace hlod {

Image resizeImage(const Image& image, int width, int height);

}  // namespace hlod
