#pragma once
// Frames encoded in memory, for HTTP answers and job frames: PNG (own writer on libdeflate,
// fast levels, so that encoding stays small beside the frame) and JPEG (libjpeg-turbo). RGBA8 in,
// alpha dropped.
#include <cstdint>
#include <string>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/Result.h"

namespace renderer {

enum class ImageFormat { Png, Jpeg };

// level: libdeflate's 1 (fastest) .. 12; quality: JPEG 1..100.
hlod::Result<std::vector<std::uint8_t>> encodePng(const hlod::Image& image, int level = 1);
hlod::Result<std::vector<std::uint8_t>> encodeJpeg(const hlod::Image& image, int quality = 85);
hlod::Result<std::vector<std::uint8_t>> encodeImage(const hlod::Image& image, ImageFormat format,
                                                    int quality = 85);
const char* mimeType(ImageFormat format);

// Writes bytes to a file, checking every step (a full disk is an Error, not a short file).
hlod::Status writeBytes(const std::string& path, const std::vector<std::uint8_t>& bytes);

}  // namespace renderer
