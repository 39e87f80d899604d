// Box-filter resize of an RGBA8 image (builder/ImageResize.h).
#include "builder/ImageResize.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

namespace hlod {

Image resizeImage(const Image& image, int width, int height) {
  Image out;
  out.width = width;
  out.height = height;
  out.pixels.resize(std::size_t(width) * height * 4);
  // OpenImageIO's box filter, one destination pixel wide: each output pixel is the mean of the
  // source pixels under it. Both buffers are wrapped, not copied; one thread (the builder prepares
  // blocks on every core already).
  const OIIO::ImageBuf src(OIIO::ImageSpec(image.width, image.height, 4, OIIO::TypeDesc::UINT8),
                           const_cast<std::uint8_t*>(image.pixels.data()));
  OIIO::ImageBuf dst(OIIO::ImageSpec(width, height, 4, OIIO::TypeDesc::UINT8), out.pixels.data());
  OIIO::ImageBufAlgo::resize(dst, src, "box", 1.0f, OIIO::ROI(0, width, 0, height, 0, 1, 0, 4), 1);
  return out;
}

}  // namespace hlod
