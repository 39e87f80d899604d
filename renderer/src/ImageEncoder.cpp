// PNG (ISO/IEC 15948: signature, IHDR, one IDAT of a zlib stream, IEND, each chunk with its
// CRC-32) written on libdeflate, and JPEG through libjpeg-turbo's TurboJPEG API.
#include "renderer/ImageEncoder.h"

#include "hlod/AtomicFile.h"

#include <turbojpeg.h>

#include <algorithm>
#include <cerrno>

#include <cstdio>
#include <cstring>
#include <memory>

#include <libdeflate.h>

namespace renderer {

namespace {

bool validImage(const hlod::Image& image) {
  return !image.empty() &&
         image.pixels.size() == static_cast<std::size_t>(image.width) * image.height * 4;
}

void putU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<std::uint8_t>(v >> s));
}

void chunk(std::vector<std::uint8_t>& out, const char type[4], const std::uint8_t* data,
           std::size_t size) {
  putU32(out, static_cast<std::uint32_t>(size));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data, data + size);
  putU32(out, libdeflate_crc32(0, out.data() + start, size + 4));
}

}  // namespace

hlod::Result<std::vector<std::uint8_t>> encodePng(const hlod::Image& image, int level) {
  if (!validImage(image)) return hlod::makeError("cannot encode an empty image");
  // Rows of RGB, each after its filter byte. Filter "up" (2) makes the flat areas of a
  // rendered frame (sky, walls) runs of zeros that deflate well at its fastest level.
  const std::size_t w = image.width, h = image.height, row = w * 3;
  std::vector<std::uint8_t> raw(h * (row + 1));
  std::vector<std::uint8_t> prev(row, 0), cur(row);
  for (std::size_t y = 0; y < h; ++y) {
    const std::uint8_t* src = &image.pixels[y * w * 4];
    for (std::size_t x = 0; x < w; ++x) std::memcpy(&cur[x * 3], &src[x * 4], 3);
    std::uint8_t* dst = &raw[y * (row + 1)];
    dst[0] = 2;
    for (std::size_t i = 0; i < row; ++i) dst[1 + i] = static_cast<std::uint8_t>(cur[i] - prev[i]);
    prev.swap(cur);
  }
  std::unique_ptr<libdeflate_compressor, decltype(&libdeflate_free_compressor)> c(
      libdeflate_alloc_compressor(std::clamp(level, 1, 12)), libdeflate_free_compressor);
  if (!c) return hlod::makeError("out of memory for the PNG compressor");
  std::vector<std::uint8_t> z(libdeflate_zlib_compress_bound(c.get(), raw.size()));
  const std::size_t zsize =
      libdeflate_zlib_compress(c.get(), raw.data(), raw.size(), z.data(), z.size());
  if (zsize == 0) return hlod::makeError("PNG compression failed");

  std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  out.reserve(zsize + 64);
  std::uint8_t ihdr[13];
  for (int i = 0; i < 4; ++i) {
    ihdr[i] = static_cast<std::uint8_t>(w >> (24 - 8 * i));
    ihdr[4 + i] = static_cast<std::uint8_t>(h >> (24 - 8 * i));
  }
  ihdr[8] = 8;   // bits per channel
  ihdr[9] = 2;   // colour type: RGB
  ihdr[10] = 0;  // deflate
  ihdr[11] = 0;  // adaptive filtering (per-row filter bytes)
  ihdr[12] = 0;  // no interlace
  chunk(out, "IHDR", ihdr, sizeof ihdr);
  chunk(out, "IDAT", z.data(), zsize);
  chunk(out, "IEND", nullptr, 0);
  return out;
}

hlod::Result<std::vector<std::uint8_t>> encodeJpeg(const hlod::Image& image, int quality) {
  if (!validImage(image)) return hlod::makeError("cannot encode an empty image");
  if (quality < 1 || quality > 100) return hlod::makeError("JPEG quality must be in 1..100");
  std::unique_ptr<void, decltype(&tjDestroy)> tj(tjInitCompress(), tjDestroy);
  if (!tj) return hlod::makeError("cannot start the JPEG encoder");
  unsigned char* buf = nullptr;
  unsigned long size = 0;
  // 4:2:0 chroma as video does; alpha is ignored (TJPF_RGBX).
  const int rc =
      tjCompress2(tj.get(), image.pixels.data(), image.width, image.width * 4, image.height,
                  TJPF_RGBX, &buf, &size, TJSAMP_420, quality, TJFLAG_FASTDCT);
  if (rc != 0) {
    if (buf) tjFree(buf);
    return hlod::makeError(std::string("JPEG encoding failed: ") + tjGetErrorStr2(tj.get()));
  }
  std::vector<std::uint8_t> out(buf, buf + size);
  tjFree(buf);
  return out;
}

hlod::Result<std::vector<std::uint8_t>> encodeImage(const hlod::Image& image, ImageFormat format,
                                                    int quality) {
  return format == ImageFormat::Png ? encodePng(image) : encodeJpeg(image, quality);
}

const char* mimeType(ImageFormat format) {
  return format == ImageFormat::Png ? "image/png" : "image/jpeg";
}

hlod::Status writeBytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  // Whole or not at all: a full disk leaves no torn frame behind.
  return hlod::writeFileAtomically(
      path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace renderer
