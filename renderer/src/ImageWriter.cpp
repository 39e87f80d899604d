// Image output: the format follows the file extension (hlod::writeImageFile checks every write).
#include "hlod/export/ImageWriter.h"
#include "renderer/Renderer.h"

namespace renderer {

hlod::Status writeImage(const std::string& path, const hlod::Image& image) {
  return hlod::writeImageFile(path, image);
}

}  // namespace renderer
