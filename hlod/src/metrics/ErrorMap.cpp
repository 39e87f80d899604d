#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include "hlod/metrics/ImageMetrics.h"

namespace hlod::metrics {

namespace {

// matplotlib's magma (S. van der Walt, N. Smith; CC0), every 16th of its 256 entries and the
// last: lightness rises monotonically from black through purple and orange to pale yellow, so
// that the error reads as brightness, also in grey print and to colour-blind readers.
constexpr std::array<std::array<float, 3>, 17> kMagma = {{
    {0.001462f, 0.000466f, 0.013866f},  // 0
    {0.039608f, 0.031090f, 0.133515f},  // 16
    {0.113094f, 0.065492f, 0.276784f},  // 32
    {0.211718f, 0.061992f, 0.418647f},  // 48
    {0.316654f, 0.071690f, 0.485380f},  // 64
    {0.414709f, 0.110431f, 0.504662f},  // 80
    {0.512831f, 0.148179f, 0.507648f},  // 96
    {0.613617f, 0.181811f, 0.498536f},  // 112
    {0.716387f, 0.214982f, 0.475290f},  // 128
    {0.816914f, 0.255895f, 0.436461f},  // 144
    {0.904281f, 0.319610f, 0.388137f},  // 160
    {0.960949f, 0.418323f, 0.359630f},  // 176
    {0.986700f, 0.535582f, 0.382210f},  // 192
    {0.996096f, 0.653659f, 0.446213f},  // 208
    {0.996898f, 0.769591f, 0.534892f},  // 224
    {0.992440f, 0.884330f, 0.640099f},  // 240
    {0.987053f, 0.991438f, 0.749504f},  // 255
}};
constexpr std::array<float, 17> kMagmaAt = {0,   16,  32,  48,  64,  80,  96,  112, 128,
                                            144, 160, 176, 192, 208, 224, 240, 255};

std::array<std::uint8_t, 3> magma(float value) {
  const float t = (std::isnan(value) ? 1.0f : std::clamp(value, 0.0f, 1.0f)) * 255.0f;
  std::size_t i = 0;
  while (i + 2 < kMagmaAt.size() && t > kMagmaAt[i + 1]) ++i;
  const float s = (t - kMagmaAt[i]) / (kMagmaAt[i + 1] - kMagmaAt[i]);
  std::array<std::uint8_t, 3> rgb{};
  for (int c = 0; c < 3; ++c) {
    const float v = kMagma[i][c] + s * (kMagma[i + 1][c] - kMagma[i][c]);
    rgb[c] = static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
  }
  return rgb;
}

}  // namespace

Image errorHeatMap(const std::vector<float>& perPixel, int width, int height) {
  if (width <= 0 || height <= 0) return {};
  const std::size_t n = static_cast<std::size_t>(width) * height;
  if (perPixel.size() != n) return {};
  Image image{width, height, std::vector<std::uint8_t>(n * 4)};
  for (std::size_t i = 0; i < n; ++i) {
    const auto rgb = magma(perPixel[i]);
    image.pixels[i * 4 + 0] = rgb[0];
    image.pixels[i * 4 + 1] = rgb[1];
    image.pixels[i * 4 + 2] = rgb[2];
    image.pixels[i * 4 + 3] = 255;
  }
  return image;
}

}  // namespace hlod::metrics
