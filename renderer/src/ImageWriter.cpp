// Image output through OpenImageIO: the format follows the file extension.
#include <OpenImageIO/imageio.h>

#include "renderer/Renderer.h"

namespace renderer {

hlod::Status writeImage(const std::string& path, const hlod::Image& image) {
  if (image.empty() ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * 4)
    return hlod::makeError(path + ": empty image");
  auto out = OIIO::ImageOutput::create(path);
  if (!out)
    return hlod::makeError(path + ": no image writer for this extension (" + OIIO::geterror() +
                           ")");
  // Frames are opaque: RGB suits every format (JPEG has no alpha). EXR stores half floats.
  const std::string format = out->format_name();
  const OIIO::TypeDesc fileType =
      format == "openexr" ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8;
  OIIO::ImageSpec spec(image.width, image.height, 3, fileType);
  if (!out->open(path, spec)) return hlod::makeError(path + ": " + out->geterror());
  // Write RGB out of the RGBA buffer by striding over alpha.
  const bool ok = out->write_image(OIIO::TypeDesc::UINT8, image.pixels.data(), 4,
                                   static_cast<OIIO::stride_t>(image.width) * 4);
  if (!ok || !out->close()) return hlod::makeError(path + ": " + out->geterror());
  return hlod::Ok{};
}

}  // namespace renderer
