#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "hlod/metrics/ImageMetrics.h"
#include "metrics/ImageInput.h"

namespace hlod::metrics {

Result<double> psnr(const Image& reference, const Image& test) {
  if (Status s = checkComparable(reference, test, "PSNR"); !s) return s.error();
  // Integer sum of squared differences: exact, so that identical images give exactly +inf and a
  // known noise pattern its closed form.
  const std::size_t n = static_cast<std::size_t>(reference.width) * reference.height;
  std::uint64_t sumSquares = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      const int d = int(reference.pixels[i * 4 + c]) - int(test.pixels[i * 4 + c]);
      sumSquares += static_cast<std::uint64_t>(d * d);
    }
  }
  if (sumSquares == 0) return std::numeric_limits<double>::infinity();
  const double mse = static_cast<double>(sumSquares) / (3.0 * static_cast<double>(n));
  return 10.0 * std::log10(255.0 * 255.0 / mse);
}

}  // namespace hlod::metrics
