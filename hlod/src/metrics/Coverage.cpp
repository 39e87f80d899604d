#include <cstddef>
#include <cstdlib>
#include <string>

#include "hlod/metrics/ImageMetrics.h"

namespace hlod::metrics {

namespace {

Status checkMask(const Mask& mask, const char* role) {
  if (mask.width <= 0 || mask.height <= 0) {
    return makeError(std::string("coverage: ") + role + " mask has no pixels");
  }
  const std::size_t expected = static_cast<std::size_t>(mask.width) * mask.height;
  if (mask.covered.size() != expected) {
    return makeError(std::string("coverage: ") + role + " mask holds " +
                     std::to_string(mask.covered.size()) + " bytes, not " +
                     std::to_string(expected) + " (width * height)");
  }
  return Ok{};
}

}  // namespace

Mask backgroundMask(const Image& image, std::array<std::uint8_t, 3> background, int tolerance) {
  if (image.width <= 0 || image.height <= 0) return {};
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  if (image.pixels.size() != n * 4) return {};
  Mask mask{image.width, image.height, std::vector<std::uint8_t>(n, 0)};
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* p = &image.pixels[i * 4];
    bool covered = false;
    for (int c = 0; c < 3; ++c) covered |= std::abs(int(p[c]) - int(background[c])) > tolerance;
    mask.covered[i] = covered ? 1 : 0;
  }
  return mask;
}

Result<double> coverageDifference(const Mask& reference, const Mask& test) {
  if (Status s = checkMask(reference, "reference"); !s) return s.error();
  if (Status s = checkMask(test, "test"); !s) return s.error();
  if (reference.width != test.width || reference.height != test.height) {
    return makeError("coverage: masks differ in size (reference " +
                     std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                     ", test " + std::to_string(test.width) + "x" + std::to_string(test.height) +
                     ")");
  }
  std::size_t differing = 0;
  for (std::size_t i = 0; i < reference.covered.size(); ++i) {
    differing += (reference.covered[i] != 0) != (test.covered[i] != 0);
  }
  return static_cast<double>(differing) / static_cast<double>(reference.covered.size());
}

Result<Image> coverageMap(const Image& frame, const Mask& reference, const Mask& test) {
  if (auto d = coverageDifference(reference, test); !d) return d.error();
  if (frame.width != test.width || frame.height != test.height ||
      frame.pixels.size() != test.covered.size() * 4)
    return makeError("coverage: the frame is not the masks' size");
  Image out = frame;
  for (std::size_t i = 0; i < test.covered.size(); ++i) {
    std::uint8_t* p = &out.pixels[i * 4];
    const bool ref = reference.covered[i] != 0, got = test.covered[i] != 0;
    const std::array<std::uint8_t, 3> rgb =
        ref == got ? std::array<std::uint8_t, 3>{std::uint8_t(p[0] / 2), std::uint8_t(p[1] / 2),
                                                 std::uint8_t(p[2] / 2)}
        : ref      ? std::array<std::uint8_t, 3>{255, 0, 0}
                   : std::array<std::uint8_t, 3>{0, 255, 255};
    p[0] = rgb[0], p[1] = rgb[1], p[2] = rgb[2], p[3] = 255;
  }
  return out;
}

}  // namespace hlod::metrics
