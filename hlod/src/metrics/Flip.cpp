// LDR-FLIP: P. Andersson, J. Nilsson, T. Akenine-Moller, M. Oskarsson, K. Astrom,
// M. D. Fairchild, "FLIP: A Difference Evaluator for Alternating Images", Proceedings of the ACM
// on Computer Graphics and Interactive Techniques 3(2), 2020 (High-Performance Graphics 2020).
//
// Per pixel, the error a viewer at a given number of pixels per degree sees when flipping
// between the reference and the test image:
//   colour pipeline: sRGB -> linear RGB -> YCxCz (the opponent space of linearised CIELAB);
//     spatial filtering of each channel with its contrast sensitivity function (a sum of
//     Gaussians whose widths, in degrees, become pixels through the pixels per degree); back to
//     linear RGB, clamped to [0, 1]; CIELAB with the Hunt adjustment; HyAB colour difference,
//     raised to q_c and redistributed to [0, 1] (p_c, p_t) against c_max, the distance between
//     green and blue: Delta E_c.
//   feature pipeline: on the achromatic channel (Y of YCxCz normalised to [0, 1]) of the
//     unfiltered images, edge (first derivative) and point (second derivative) detectors from
//     Gaussians of width w degrees; the larger difference in their magnitudes, normalised by
//     1/sqrt(2) and raised to q_f: Delta E_f.
//   Delta E = Delta E_c ^ (1 - Delta E_f): features sharpen colour differences at edges and
//     points.
// The constants and the order of the steps were checked against the authors' public code; the
// code here is written from the paper's equations. Borders repeat the edge pixels (as the
// authors' code does).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <string>
#include <vector>

#include "hlod/metrics/ImageMetrics.h"
#include "metrics/ImageInput.h"
#include "metrics/SeparableFilter.h"

namespace hlod::metrics {

namespace {

// The paper's constants of the colour and feature pipelines.
struct FlipConstants {
  double q_c = 0.7;   // exponent of the HyAB colour difference
  double p_c = 0.4;   // share of c_max below which errors are compressed ...
  double p_t = 0.95;  // ... into [0, p_t]; the rest of [p_c c_max, c_max] maps to (p_t, 1]
  double w = 0.082;   // feature detector width, degrees
  double q_f = 0.5;   // exponent of the feature difference
};
constexpr FlipConstants kFlip;

// A contrast sensitivity function in the spatial domain as the paper gives it, a sum of two
// Gaussians over the distance x in degrees:
//   S(x) = a1 sqrt(pi / b1) exp(-pi^2 x^2 / b1) + a2 sqrt(pi / b2) exp(-pi^2 x^2 / b2).
struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kCsfA{1.0, 0.0047, 0.0, 1e-5};    // achromatic (Y)
constexpr Csf kCsfRG{1.0, 0.0053, 0.0, 1e-5};   // red-green (Cx)
constexpr Csf kCsfBY{34.1, 0.04, 13.5, 0.025};  // blue-yellow (Cz)
constexpr double kMaxCsfB = 0.04;               // the widest Gaussian of the three

// Largest pixels per degree accepted: the filters grow with it (a radius of ~135 pixels here).
constexpr double kMaxPixelsPerDegree = 1000.0;

// sRGB (D65) primaries: linear RGB -> XYZ and back.
constexpr double kRgbToXyz[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                    {0.2126729, 0.7151522, 0.0721750},
                                    {0.0193339, 0.1191920, 0.9503041}};
constexpr double kXyzToRgb[3][3] = {{3.2404542, -1.5371385, -0.4985314},
                                    {-0.9692660, 1.8760108, 0.0415560},
                                    {0.0556434, -0.2040259, 1.0572252}};
// The reference white: XYZ of linear RGB (1, 1, 1).
constexpr std::array<double, 3> kWhite = {kRgbToXyz[0][0] + kRgbToXyz[0][1] + kRgbToXyz[0][2],
                                          kRgbToXyz[1][0] + kRgbToXyz[1][1] + kRgbToXyz[1][2],
                                          kRgbToXyz[2][0] + kRgbToXyz[2][1] + kRgbToXyz[2][2]};

using Vec3 = std::array<double, 3>;

Vec3 multiply(const double (&m)[3][3], const Vec3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
          m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

double srgbToLinear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// YCxCz: CIELAB without its cube root, so that it is linear in XYZ and may be filtered.
Vec3 linearRgbToYcxcz(const Vec3& rgb) {
  const Vec3 xyz = multiply(kRgbToXyz, rgb);
  const double x = xyz[0] / kWhite[0], y = xyz[1] / kWhite[1], z = xyz[2] / kWhite[2];
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Vec3 ycxczToLinearRgb(const Vec3& ycxcz) {
  const double y = (ycxcz[0] + 16.0) / 116.0;
  const double x = y + ycxcz[1] / 500.0;
  const double z = y - ycxcz[2] / 200.0;
  return multiply(kXyzToRgb, Vec3{x * kWhite[0], y * kWhite[1], z * kWhite[2]});
}

// CIELAB of a linear RGB colour, then the Hunt adjustment (a and b scaled by 0.01 L), which
// makes chroma count less where it is dark, as a viewer perceives it.
Vec3 huntLab(const Vec3& rgb) {
  const Vec3 xyz = multiply(kRgbToXyz, rgb);
  constexpr double delta = 6.0 / 29.0;
  const auto f = [](double t) {
    return t > delta * delta * delta ? std::cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0;
  };
  const double fx = f(xyz[0] / kWhite[0]), fy = f(xyz[1] / kWhite[1]), fz = f(xyz[2] / kWhite[2]);
  const double l = 116.0 * fy - 16.0;
  const double a = 500.0 * (fx - fy);
  const double b = 200.0 * (fy - fz);
  return {l, 0.01 * l * a, 0.01 * l * b};
}

// HyAB: city-block distance in lightness plus Euclidean distance in the chromatic plane.
double hyab(const Vec3& p, const Vec3& q) {
  const double da = p[1] - q[1], db = p[2] - q[2];
  return std::abs(p[0] - q[0]) + std::sqrt(da * da + db * db);
}

// c_max: the HyAB^q_c distance between green and blue, the largest between any two colours
// after the Hunt adjustment.
double cMax() {
  return std::pow(hyab(huntLab({0.0, 1.0, 0.0}), huntLab({0.0, 0.0, 1.0})), kFlip.q_c);
}

struct Ycxcz {
  Plane<float> y, cx, cz;
};

Ycxcz toYcxcz(const Image& image) {
  std::array<double, 256> linear{};
  for (int i = 0; i < 256; ++i) linear[i] = srgbToLinear(i / 255.0);
  const int w = image.width, h = image.height;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  Ycxcz out{
      {w, h, std::vector<float>(n)}, {w, h, std::vector<float>(n)}, {w, h, std::vector<float>(n)}};
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* p = &image.pixels[i * 4];
    const Vec3 c = linearRgbToYcxcz({linear[p[0]], linear[p[1]], linear[p[2]]});
    out.y.values[i] = static_cast<float>(c[0]);
    out.cx.values[i] = static_cast<float>(c[1]);
    out.cz.values[i] = static_cast<float>(c[2]);
  }
  return out;
}

// The spatial filter of one channel as 1D factors f_k with kernel(i, j) = sum_k f_k(i) f_k(j),
// normalised to unit sum: each Gaussian of the CSF is separable, exp(-pi^2 (i^2 + j^2) dx^2 / b)
// = e(i) e(j), and the 2D sum of c e(i) e(j) is c E^2 with E = sum_i e(i).
std::vector<std::vector<float>> csfFactors(const Csf& csf, double pixelsPerDegree, int radius) {
  const double dx = 1.0 / pixelsPerDegree;  // degrees per pixel
  const double pi = std::numbers::pi;
  const auto gaussian = [&](double a, double b, std::vector<double>& e) {
    double sum = 0.0;
    for (int i = -radius; i <= radius; ++i) {
      e.push_back(std::exp(-pi * pi * (i * dx) * (i * dx) / b));
      sum += e.back();
    }
    return std::pair{a * std::sqrt(pi / b), sum};  // c and E
  };
  std::vector<double> e1, e2;
  const auto [c1, sum1] = gaussian(csf.a1, csf.b1, e1);
  const auto [c2, sum2] = gaussian(csf.a2, csf.b2, e2);
  const double total = c1 * sum1 * sum1 + c2 * sum2 * sum2;
  std::vector<std::vector<float>> factors;
  for (const auto& [c, e] : {std::pair{c1, &e1}, std::pair{c2, &e2}}) {
    if (c == 0.0) continue;  // a2 = 0: a single Gaussian
    const double scale = std::sqrt(c / total);
    std::vector<float> f(e->size());
    for (std::size_t i = 0; i < f.size(); ++i) f[i] = static_cast<float>(scale * (*e)[i]);
    factors.push_back(std::move(f));
  }
  return factors;
}

Plane<float> filterChannel(const Plane<float>& in, const std::vector<std::vector<float>>& factors) {
  Plane<float> out{in.width, in.height, std::vector<float>(in.values.size(), 0.0f)};
  for (const std::vector<float>& f : factors) {
    const Plane<float> part = convolveClamped<float>(in, f, f);
    for (std::size_t i = 0; i < out.values.size(); ++i) out.values[i] += part.values[i];
  }
  return out;
}

// Colour pipeline: Delta E_c per pixel, in [0, 1].
std::vector<float> colourDifference(const Ycxcz& reference, const Ycxcz& test,
                                    double pixelsPerDegree) {
  // One radius for the three channels: three standard deviations of the widest Gaussian,
  // sigma = sqrt(b / (2 pi^2)) degrees.
  const double pi = std::numbers::pi;
  const int radius =
      static_cast<int>(std::ceil(3.0 * std::sqrt(kMaxCsfB / (2.0 * pi * pi)) * pixelsPerDegree));
  const auto fA = csfFactors(kCsfA, pixelsPerDegree, radius);
  const auto fRG = csfFactors(kCsfRG, pixelsPerDegree, radius);
  const auto fBY = csfFactors(kCsfBY, pixelsPerDegree, radius);
  const auto filtered = [&](const Ycxcz& c) {
    return Ycxcz{filterChannel(c.y, fA), filterChannel(c.cx, fRG), filterChannel(c.cz, fBY)};
  };
  const Ycxcz r = filtered(reference);
  const Ycxcz t = filtered(test);

  const double cmax = cMax();
  const double pccmax = kFlip.p_c * cmax;
  const auto perceived = [](const Ycxcz& c, std::size_t i) {
    Vec3 rgb = ycxczToLinearRgb({c.y.values[i], c.cx.values[i], c.cz.values[i]});
    for (double& v : rgb) v = std::clamp(v, 0.0, 1.0);  // filtering may leave the gamut
    return huntLab(rgb);
  };
  std::vector<float> out(r.y.values.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double e = std::pow(hyab(perceived(r, i), perceived(t, i)), kFlip.q_c);
    // Redistribution: the small errors, where most of the visible ones lie, get [0, p_t].
    const double deltaEc = e < pccmax
                               ? kFlip.p_t / pccmax * e
                               : kFlip.p_t + (e - pccmax) / (cmax - pccmax) * (1.0 - kFlip.p_t);
    out[i] = static_cast<float>(deltaEc);
  }
  return out;
}

// Feature detectors, 1D: the Gaussian g (unit sum) and its first and second derivatives dg and
// ddg, each with positive weights summing to 1 and negative ones to -1. A 2D detector is a
// derivative along one axis times g along the other.
struct FeatureKernels {
  std::vector<float> g, dg, ddg;
};

FeatureKernels featureKernels(double pixelsPerDegree) {
  const double sigma = 0.5 * kFlip.w * pixelsPerDegree;  // pixels
  const int radius = static_cast<int>(std::ceil(3.0 * sigma));
  std::vector<double> g, dg, ddg;
  for (int i = -radius; i <= radius; ++i) {
    const double gi = std::exp(-(i * i) / (2.0 * sigma * sigma));
    g.push_back(gi);
    dg.push_back(-i * gi);
    ddg.push_back((i * i / (sigma * sigma) - 1.0) * gi);
  }
  const auto normalised = [](const std::vector<double>& k, bool bySign) {
    double positive = 0.0, negative = 0.0;
    for (double v : k) (v > 0.0 ? positive : negative) += std::abs(v);
    std::vector<float> out(k.size(), 0.0f);
    for (std::size_t i = 0; i < k.size(); ++i) {
      const double sum = !bySign ? positive : k[i] > 0.0 ? positive : negative;
      // A detector narrower than a pixel (tiny pixels per degree) underflows: it sees nothing.
      if (sum > 0.0) out[i] = static_cast<float>(k[i] / sum);
    }
    return out;
  };
  return {normalised(g, false), normalised(dg, true), normalised(ddg, true)};
}

// Feature pipeline: Delta E_f per pixel, in [0, 1].
std::vector<float> featureDifference(const Ycxcz& reference, const Ycxcz& test,
                                     double pixelsPerDegree) {
  const FeatureKernels k = featureKernels(pixelsPerDegree);
  struct Features {
    std::vector<float> edge, point;  // gradient and second-derivative magnitudes
  };
  const auto features = [&](const Plane<float>& y) {
    // The achromatic channel normalised to [0, 1].
    Plane<float> a{y.width, y.height, std::vector<float>(y.values.size())};
    for (std::size_t i = 0; i < a.values.size(); ++i) a.values[i] = (y.values[i] + 16.0f) / 116.0f;
    const Plane<float> ex = convolveClamped<float>(a, k.dg, k.g);
    const Plane<float> ey = convolveClamped<float>(a, k.g, k.dg);
    const Plane<float> px = convolveClamped<float>(a, k.ddg, k.g);
    const Plane<float> py = convolveClamped<float>(a, k.g, k.ddg);
    Features f{std::vector<float>(a.values.size()), std::vector<float>(a.values.size())};
    for (std::size_t i = 0; i < a.values.size(); ++i) {
      f.edge[i] = std::sqrt(ex.values[i] * ex.values[i] + ey.values[i] * ey.values[i]);
      f.point[i] = std::sqrt(px.values[i] * px.values[i] + py.values[i] * py.values[i]);
    }
    return f;
  };
  const Features r = features(reference.y);
  const Features t = features(test.y);
  std::vector<float> out(r.edge.size());
  const double normalisation = 1.0 / std::sqrt(2.0);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double edge = std::abs(double(r.edge[i]) - double(t.edge[i]));
    const double point = std::abs(double(r.point[i]) - double(t.point[i]));
    out[i] = static_cast<float>(std::pow(normalisation * std::max(edge, point), kFlip.q_f));
  }
  return out;
}

}  // namespace

Result<std::vector<float>> flipMap(const Image& reference, const Image& test,
                                   double pixelsPerDegree) {
  if (Status s = checkComparable(reference, test, "FLIP"); !s) return s.error();
  if (!(pixelsPerDegree > 0.0 && pixelsPerDegree <= kMaxPixelsPerDegree)) {
    return makeError("FLIP: pixels per degree must lie in (0, " +
                     std::to_string(kMaxPixelsPerDegree) + "], not " +
                     std::to_string(pixelsPerDegree));
  }
  const Ycxcz r = toYcxcz(reference);
  const Ycxcz t = toYcxcz(test);
  const std::vector<float> deltaEc = colourDifference(r, t, pixelsPerDegree);
  const std::vector<float> deltaEf = featureDifference(r, t, pixelsPerDegree);
  std::vector<float> deltaE(deltaEc.size());
  for (std::size_t i = 0; i < deltaE.size(); ++i) {
    // Clamped because c_max bounds Delta E_c only up to rounding.
    deltaE[i] = std::clamp(std::pow(deltaEc[i], 1.0f - deltaEf[i]), 0.0f, 1.0f);
  }
  return deltaE;
}

Result<double> flip(const Image& reference, const Image& test, double pixelsPerDegree) {
  Result<std::vector<float>> map = flipMap(reference, test, pixelsPerDegree);
  if (!map) return map.error();
  double sum = 0.0;
  for (float v : *map) sum += v;
  return sum / static_cast<double>(map->size());
}

}  // namespace hlod::metrics
