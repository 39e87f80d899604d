// writeImageFile: OpenImageIO encodes into memory, the bytes go to disk through checked stdio.
// OIIO's own file output does not report a failed write or close (a PNG to a full disk "succeeded"
// with exit 0), so it never touches the file itself.
#include "hlod/export/ImageWriter.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <system_error>
#include <vector>

namespace hlod {

namespace fs = std::filesystem;

namespace {

Status writeBytes(const fs::path& path, const std::vector<unsigned char>& bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return makeError("cannot write " + path.string() + ": " + std::strerror(errno));
  // The first failure's errno: a full disk shows at the write, the flush or only the close.
  int error = 0;
  if (std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fflush(f) != 0)
    error = errno ? errno : EIO;
  if (std::fclose(f) != 0 && error == 0) error = errno ? errno : EIO;
  if (error == 0) return Ok{};
  // Remove the truncated file, but never what a link points to (a device, someone's file).
  std::error_code ec;
  if (fs::is_regular_file(fs::symlink_status(path, ec))) fs::remove(path, ec);
  return makeError("cannot write " + path.string() + ": " + std::strerror(error));
}

}  // namespace

Status writeImageFile(const fs::path& path, const Image& image, const ImageWriteOptions& options) {
  if (image.empty() ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * 4)
    return makeError(path.string() + ": empty image");
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out)
    return makeError(path.string() + ": no image writer for this extension (" + OIIO::geterror() +
                     ")");
  if (!out->supports("ioproxy"))
    return makeError(path.string() + ": the " + out->format_name() +
                     " writer cannot encode into memory; use .png, .jpg, .bmp, .tif or .exr");
  const std::string format = out->format_name();
  const bool alpha = options.alpha && format != "jpeg";  // JPEG has no alpha
  const OIIO::TypeDesc fileType =
      format == "openexr" ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8;
  OIIO::ImageSpec spec(image.width, image.height, alpha ? 4 : 3, fileType);
  if (options.fastPng) {
    spec.attribute("png:compressionLevel", 1);
    spec.attribute("png:filter", 0x08);  // PNG_FILTER_NONE: faster and, on noise, smaller
  }
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  out->set_ioproxy(&memory);
  if (!out->open(path.string(), spec)) return makeError(path.string() + ": " + out->geterror());
  // RGB out of the RGBA buffer by striding over alpha.
  const bool ok = out->write_image(OIIO::TypeDesc::UINT8, image.pixels.data(), 4,
                                   static_cast<OIIO::stride_t>(image.width) * 4);
  if (!ok || !out->close()) return makeError(path.string() + ": " + out->geterror());
  return writeBytes(path, bytes);
}

}  // namespace hlod
