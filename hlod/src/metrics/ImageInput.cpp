#include "metrics/ImageInput.h"

#include <cassert>
#include <cstddef>
#include <string>

namespace hlod::metrics {

Status checkImage(const Image& image, std::string_view metric, std::string_view role) {
  const std::string what = std::string(metric) + ": " + std::string(role) + " image";
  if (image.width <= 0 || image.height <= 0) {
    return makeError(what + " has no pixels (" + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + ")");
  }
  const std::size_t expected =
      static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4;
  if (image.pixels.size() != expected) {
    return makeError(what + " holds " + std::to_string(image.pixels.size()) + " bytes, not " +
                     std::to_string(expected) + " (width * height * 4)");
  }
  return Ok{};
}

Status checkComparable(const Image& reference, const Image& test, std::string_view metric) {
  if (Status s = checkImage(reference, metric, "reference"); !s) return s;
  if (Status s = checkImage(test, metric, "test"); !s) return s;
  if (reference.width != test.width || reference.height != test.height) {
    return makeError(std::string(metric) + ": images differ in size (reference " +
                     std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                     ", test " + std::to_string(test.width) + "x" + std::to_string(test.height) +
                     ")");
  }
  return Ok{};
}

std::vector<double> luma601(const Image& image) {
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  assert(image.pixels.size() == n * 4);
  std::vector<double> y(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* p = &image.pixels[i * 4];
    y[i] = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
  }
  return y;
}

}  // namespace hlod::metrics
