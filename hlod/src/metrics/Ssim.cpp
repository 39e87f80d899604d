// SSIM: Z. Wang, A. C. Bovik, H. R. Sheikh, E. P. Simoncelli, "Image Quality Assessment: From
// Error Visibility to Structural Similarity", IEEE Transactions on Image Processing 13(4), 2004.
// Eq. (13) with the paper's constants and window (sec. III-B): an 11x11 circular-symmetric
// Gaussian of standard deviation 1.5 samples, normalised to unit sum; mean SSIM (eq. 17) over the
// windows that lie wholly inside the image, as the authors' ssim_index.m ('valid' filtering).
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "hlod/metrics/ImageMetrics.h"
#include "metrics/ImageInput.h"
#include "metrics/SeparableFilter.h"

namespace hlod::metrics {

namespace {

constexpr int kWindowRadius = 5;  // 11 taps
constexpr double kSigma = 1.5;
constexpr double kK1 = 0.01;
constexpr double kK2 = 0.03;
constexpr double kL = 255.0;  // dynamic range of the 8-bit luma

// The 1D factor of the separable window, normalised: the product of two normalised 1D
// Gaussians is the normalised 2D one.
std::vector<double> gaussianWindow() {
  std::vector<double> w(2 * kWindowRadius + 1);
  double sum = 0.0;
  for (int i = -kWindowRadius; i <= kWindowRadius; ++i) {
    w[i + kWindowRadius] = std::exp(-(i * i) / (2.0 * kSigma * kSigma));
    sum += w[i + kWindowRadius];
  }
  for (double& v : w) v /= sum;
  return w;
}

// The SSIM of each whole window, in double precision: (W - 10) x (H - 10) values.
Result<Plane<double>> computeSsimMap(const Image& reference, const Image& test) {
  if (Status s = checkComparable(reference, test, "SSIM"); !s) return s.error();
  constexpr int kWindow = 2 * kWindowRadius + 1;
  if (reference.width < kWindow || reference.height < kWindow) {
    return makeError("SSIM: images of " + std::to_string(reference.width) + "x" +
                     std::to_string(reference.height) +
                     " hold no whole 11x11 window (at least 11x11 needed)");
  }
  const int w = reference.width;
  const int h = reference.height;
  const Plane<double> x{w, h, luma601(reference)};
  const Plane<double> y{w, h, luma601(test)};
  Plane<double> xx{w, h, std::vector<double>(x.values.size())};
  Plane<double> yy = xx;
  Plane<double> xy = xx;
  for (std::size_t i = 0; i < x.values.size(); ++i) {
    xx.values[i] = x.values[i] * x.values[i];
    yy.values[i] = y.values[i] * y.values[i];
    xy.values[i] = x.values[i] * y.values[i];
  }
  // Local means, variances and covariance under the Gaussian window (eqs. 14-16).
  const std::vector<double> g = gaussianWindow();
  const std::span<const double> k(g);
  const Plane<double> muX = convolveValid(x, k, k);
  const Plane<double> muY = convolveValid(y, k, k);
  const Plane<double> eXX = convolveValid(xx, k, k);
  const Plane<double> eYY = convolveValid(yy, k, k);
  const Plane<double> eXY = convolveValid(xy, k, k);

  // Eq. (13); C1 = (K1 L)^2 and C2 = (K2 L)^2 keep it stable where means or variances are ~0.
  const double c1 = (kK1 * kL) * (kK1 * kL);
  const double c2 = (kK2 * kL) * (kK2 * kL);
  Plane<double> map{muX.width, muX.height, std::vector<double>(muX.values.size())};
  for (std::size_t i = 0; i < map.values.size(); ++i) {
    const double mx = muX.values[i];
    const double my = muY.values[i];
    const double mx2 = mx * mx;
    const double my2 = my * my;
    const double mxy = mx * my;
    const double sx2 = eXX.values[i] - mx2;
    const double sy2 = eYY.values[i] - my2;
    const double sxy = eXY.values[i] - mxy;
    const double numerator = (2.0 * mxy + c1) * (2.0 * sxy + c2);
    const double denominator = (mx2 + my2 + c1) * (sx2 + sy2 + c2);
    map.values[i] = numerator / denominator;
  }
  return map;
}

}  // namespace

Result<ScalarMap> ssimMap(const Image& reference, const Image& test) {
  Result<Plane<double>> map = computeSsimMap(reference, test);
  if (!map) return map.error();
  ScalarMap out{map->width, map->height, std::vector<float>(map->values.size())};
  for (std::size_t i = 0; i < out.values.size(); ++i) {
    out.values[i] = static_cast<float>(map->values[i]);
  }
  return out;
}

Result<double> ssim(const Image& reference, const Image& test) {
  // The mean of the double values, not of the float map, so that identical images give exactly
  // 1 and closed forms hold to double precision.
  Result<Plane<double>> map = computeSsimMap(reference, test);
  if (!map) return map.error();
  double sum = 0.0;
  for (double v : map->values) sum += v;
  return sum / static_cast<double>(map->values.size());
}

}  // namespace hlod::metrics
