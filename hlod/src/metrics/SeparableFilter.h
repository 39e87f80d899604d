#pragma once
// Separable 2D convolution of a plane of values (private to metrics/): a horizontal pass with one
// odd-sized kernel, then a vertical pass with another. Two border treatments: 'valid' (only
// outputs whose window lies wholly inside the plane, as SSIM's reference code) and clamp-to-edge
// (same size out as in, as FLIP's reference code).
#include <algorithm>
#include <cassert>
#include <cstddef>
#include <span>
#include <vector>

namespace hlod::metrics {

template <class T>
struct Plane {
  int width = 0;
  int height = 0;
  std::vector<T> values;  // width * height, row 0 at the top

  T at(int x, int y) const { return values[static_cast<std::size_t>(y) * width + x]; }
};

// Kernels have 2r + 1 taps, tap k weighting the input at offset k - r. The result is
// (width - 2 rx) x (height - 2 ry); the input must be at least (2 rx + 1) x (2 ry + 1).
template <class T>
Plane<T> convolveValid(const Plane<T>& in, std::span<const T> kx, std::span<const T> ky) {
  assert(kx.size() % 2 == 1 && ky.size() % 2 == 1);
  const int rx = static_cast<int>(kx.size() / 2);
  const int ry = static_cast<int>(ky.size() / 2);
  assert(in.width > 2 * rx && in.height > 2 * ry);
  const int w = in.width - 2 * rx;
  const int h = in.height - 2 * ry;
  // Horizontal pass over every input row: in.height x w.
  std::vector<T> rows(static_cast<std::size_t>(in.height) * w);
  for (int y = 0; y < in.height; ++y) {
    const T* src = &in.values[static_cast<std::size_t>(y) * in.width];
    T* dst = &rows[static_cast<std::size_t>(y) * w];
    for (int x = 0; x < w; ++x) {
      T sum = 0;
      for (std::size_t k = 0; k < kx.size(); ++k) sum += kx[k] * src[x + k];
      dst[x] = sum;
    }
  }
  // Vertical pass, a row at a time so that the inner loop runs along memory.
  Plane<T> out{w, h, std::vector<T>(static_cast<std::size_t>(w) * h, T(0))};
  for (int y = 0; y < h; ++y) {
    T* dst = &out.values[static_cast<std::size_t>(y) * w];
    for (std::size_t k = 0; k < ky.size(); ++k) {
      const T* src = &rows[(static_cast<std::size_t>(y) + k) * w];
      const T weight = ky[k];
      for (int x = 0; x < w; ++x) dst[x] += weight * src[x];
    }
  }
  return out;
}

// The same kernels with the input's edge pixels repeated outwards: the result has the input's
// size.
template <class T>
Plane<T> convolveClamped(const Plane<T>& in, std::span<const T> kx, std::span<const T> ky) {
  assert(kx.size() % 2 == 1 && ky.size() % 2 == 1);
  const int rx = static_cast<int>(kx.size() / 2);
  const int ry = static_cast<int>(ky.size() / 2);
  const int w = in.width;
  const int h = in.height;
  std::vector<T> rows(static_cast<std::size_t>(w) * h);
  // Horizontal pass: the row padded by rx repeated edge values on each side, then a plain sum.
  std::vector<T> padded(static_cast<std::size_t>(w) + 2 * rx);
  for (int y = 0; y < h; ++y) {
    const T* src = &in.values[static_cast<std::size_t>(y) * w];
    for (int i = 0; i < w + 2 * rx; ++i) padded[i] = src[std::clamp(i - rx, 0, w - 1)];
    T* dst = &rows[static_cast<std::size_t>(y) * w];
    for (int x = 0; x < w; ++x) {
      T sum = 0;
      for (std::size_t k = 0; k < kx.size(); ++k) sum += kx[k] * padded[x + k];
      dst[x] = sum;
    }
  }
  Plane<T> out{w, h, std::vector<T>(static_cast<std::size_t>(w) * h, T(0))};
  for (int y = 0; y < h; ++y) {
    T* dst = &out.values[static_cast<std::size_t>(y) * w];
    for (int k = 0; k < static_cast<int>(ky.size()); ++k) {
      const int yy = std::clamp(y + k - ry, 0, h - 1);
      const T* src = &rows[static_cast<std::size_t>(yy) * w];
      const T weight = ky[k];
      for (int x = 0; x < w; ++x) dst[x] += weight * src[x];
    }
  }
  return out;
}

}  // namespace hlod::metrics
