// loadImage: any format OpenImageIO reads, converted to RGBA8 with row 0 at the top.
#include <OpenImageIO/imageio.h>

#include "hlod/import/Import.h"
#include "import/ImportUtil.h"

namespace hlod {

Result<Image> loadImage(const std::filesystem::path& path) {
  using import::fileError;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return fileError(path, "image file not found");
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) {
    std::string why = OIIO::geterror();
    return fileError(path, "cannot read image" + (why.empty() ? "" : ": " + why));
  }
  const OIIO::ImageSpec& spec = in->spec();
  const int w = spec.width, h = spec.height, ch = spec.nchannels;
  // Reject sizes that would overflow or exhaust memory before allocating.
  if (w <= 0 || h <= 0 || ch <= 0 || static_cast<long long>(w) * h > (1LL << 28))
    return fileError(path, "unsupported image size " + std::to_string(w) + "x" + std::to_string(h));
  std::vector<std::uint8_t> raw;
  try {
    raw.resize(static_cast<std::size_t>(w) * h * ch);
  } catch (const std::bad_alloc&) {
    return fileError(path, "image too large");
  }
  if (!in->read_image(0, 0, 0, ch, OIIO::TypeDesc::UINT8, raw.data())) {
    std::string why = in->geterror();
    return fileError(path, "cannot decode image" + (why.empty() ? "" : ": " + why));
  }
  in->close();
  Image image;
  image.width = w;
  image.height = h;
  image.pixels.resize(static_cast<std::size_t>(w) * h * 4);
  const std::size_t count = static_cast<std::size_t>(w) * h;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint8_t* s = &raw[i * ch];
    std::uint8_t* d = &image.pixels[i * 4];
    if (ch == 1 || ch == 2) {  // grey, grey + alpha
      d[0] = d[1] = d[2] = s[0];
      d[3] = ch == 2 ? s[1] : 255;
    } else {
      d[0] = s[0];
      d[1] = s[1];
      d[2] = s[2];
      d[3] = ch >= 4 ? s[3] : 255;
    }
  }
  return image;
}

}  // namespace hlod
