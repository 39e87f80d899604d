#pragma once
// Hand-built inputs of the metrics tests and of metrics_bench: images (flat, textured) and
// meshes (a gridded square, a rippled one).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/metrics/ImageMetrics.h"

namespace hlod::metrics::test {

using Rgb = std::array<std::uint8_t, 3>;

inline Image solid(int w, int h, Rgb rgb) {
  Image image{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h * 4, 255)};
  for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
    for (int c = 0; c < 3; ++c) image.pixels[i + c] = rgb[c];
  }
  return image;
}

inline void set(Image& image, int x, int y, Rgb rgb) {
  for (int c = 0; c < 3; ++c)
    image.pixels[(static_cast<std::size_t>(y) * image.width + x) * 4 + c] = rgb[c];
}

inline std::uint8_t& channel(Image& image, int x, int y, int c) {
  return image.pixels[(static_cast<std::size_t>(y) * image.width + x) * 4 + c];
}

// A deterministic texture with values in [lo, hi]: gradients, stripes and hashed noise, so that
// windows differ in mean, variance and structure.
inline Image texture(int w, int h, int lo = 10, int hi = 245) {
  Image image = solid(w, h, {0, 0, 0});
  std::uint32_t state = 12345;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        state = state * 1664525u + 1013904223u;
        const double smooth = 0.5 + 0.25 * std::sin(0.11 * x + 0.7 * c) * std::cos(0.07 * y);
        const double stripes = ((x / 3 + y / 5 + c) % 2) * 0.15;
        const double noise = ((state >> 24) / 255.0 - 0.5) * 0.2;
        const double v = std::clamp(smooth + stripes + noise, 0.0, 1.0);
        channel(image, x, y, c) = static_cast<std::uint8_t>(lo + std::lround(v * (hi - lo)));
      }
    }
  }
  return image;
}

// A 640x360 frame and the same frame with a ninth of it (200 x 100 pixels) painted green.
struct FramePair {
  Image reference, test;
};
inline FramePair frameWithAChangedNinth() {
  FramePair p{texture(640, 360), {}};
  p.test = p.reference;
  for (int y = 100; y < 200; ++y) {
    for (int x = 200; x < 400; ++x) set(p.test, x, y, {30, 160, 90});
  }
  return p;
}

// The square [0, 1]^2 at height z, as n x n quads of two triangles each.
inline Mesh square(int n, double z = 0.0) {
  Mesh m;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) m.positions.push_back({double(i) / n, double(j) / n, z});
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
  }
  return m;
}

// square(n) rippled to z = amplitude sin(4 pi x) cos(4 pi y): two whole periods along x and
// along y, whose crests lie on grid vertices when n is a multiple of 8.
inline Mesh rippledSquare(int n, double amplitude) {
  const double k = 4.0 * std::numbers::pi;
  Mesh m = square(n);
  for (glm::dvec3& p : m.positions) p.z = amplitude * std::sin(k * p.x) * std::cos(k * p.y);
  return m;
}

}  // namespace hlod::metrics::test
