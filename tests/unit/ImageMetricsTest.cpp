#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "MetricsTestInputs.h"
#include "hlod/metrics/ImageMetrics.h"

namespace hlod::metrics {
namespace {

using test::channel;
using test::Rgb;
using test::set;
using test::solid;
using test::texture;

double meanOf(const std::vector<float>& v) {
  double sum = 0.0;
  for (float x : v) sum += x;
  return sum / static_cast<double>(v.size());
}

// --- PSNR, SSIM, FLIP on identical images ---------------------------------------------------

TEST(ImageMetrics, IdenticalImagesGivePsnrInfinitySsimOneAndFlipZero) {
  const Image a = texture(64, 48);
  const Image b = a;
  const Result<double> p = psnr(a, b);
  ASSERT_TRUE(p.ok()) << p.message();
  EXPECT_EQ(*p, std::numeric_limits<double>::infinity());
  const Result<double> s = ssim(a, b);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(*s, 1.0);
  const Result<double> f = flip(a, b);
  ASSERT_TRUE(f.ok()) << f.message();
  EXPECT_EQ(*f, 0.0);
  const Result<std::vector<float>> map = flipMap(a, b);
  ASSERT_TRUE(map.ok());
  EXPECT_EQ(*std::max_element(map->begin(), map->end()), 0.0f);
}

// --- PSNR ------------------------------------------------------------------------------------

TEST(ImageMetrics, PsnrOfAKnownNoisePatternIsItsClosedForm) {
  // R +-3 on a checkerboard, G +5 on one pixel in four, B -7 on every fourth column: squared
  // errors average 9, 25 / 4 and 49 / 4 over the channels' pixels.
  const int w = 64, h = 48;
  const Image reference = texture(w, h);
  Image test = reference;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      channel(test, x, y, 0) += (x + y) % 2 == 0 ? 3 : -3;
      if (x % 2 == 0 && y % 2 == 0) channel(test, x, y, 1) += 5;
      if (x % 4 == 0) channel(test, x, y, 2) -= 7;
      channel(test, x, y, 3) = 0;  // alpha does not count
    }
  }
  const double mse = (9.0 + 25.0 / 4.0 + 49.0 / 4.0) / 3.0;
  const Result<double> p = psnr(reference, test);
  ASSERT_TRUE(p.ok()) << p.message();
  EXPECT_NEAR(*p, 20.0 * std::log10(255.0 / std::sqrt(mse)), 1e-9);
}

TEST(ImageMetrics, PsnrOfBlackAgainstWhiteIsZero) {
  const Result<double> p = psnr(solid(8, 8, {0, 0, 0}), solid(8, 8, {255, 255, 255}));
  ASSERT_TRUE(p.ok());
  EXPECT_NEAR(*p, 0.0, 1e-12);
}

// --- SSIM ------------------------------------------------------------------------------------

// The luminance term of SSIM (Wang et al. eq. 6) with C1 = (0.01 * 255)^2.
double luminanceTerm(double mx, double my) {
  const double c1 = (0.01 * 255.0) * (0.01 * 255.0);
  return (2.0 * mx * my + c1) / (mx * mx + my * my + c1);
}

TEST(ImageMetrics, SsimOfAConstantOffsetOnAFlatImageIsTheLuminanceTerm) {
  // Flat images: no variance, so the contrast-structure term is (0 + C2) / (0 + C2) = 1 and each
  // window's SSIM is the luminance term of the two (window-weighted) means.
  for (const int d : {10, 40, 100}) {
    const Result<double> s = ssim(
        solid(32, 24, {100, 100, 100}),
        solid(32, 24, Rgb{std::uint8_t(100 + d), std::uint8_t(100 + d), std::uint8_t(100 + d)}));
    ASSERT_TRUE(s.ok()) << s.message();
    EXPECT_NEAR(*s, luminanceTerm(100.0, 100.0 + d), 1e-12) << "offset " << d;
  }
}

TEST(ImageMetrics, SsimOfAConstantOffsetOnATextureLiesBetweenTheLuminanceTermsOfItsExtremes) {
  // An offset leaves variances and covariance unchanged (contrast-structure term 1), so each
  // window's SSIM is 1 - d^2 / (m^2 + (m + d)^2 + C1), which rises with the window mean m: the
  // mean SSIM lies between the values at the darkest and the brightest luma.
  const int d = 20;
  const Image reference = texture(48, 40, 30, 200);
  Image test = reference;
  for (std::size_t i = 0; i < test.pixels.size(); ++i) {
    if (i % 4 != 3) test.pixels[i] += d;
  }
  double lo = 255.0, hi = 0.0;
  for (std::size_t i = 0; i < reference.pixels.size(); i += 4) {
    const double y = 0.299 * reference.pixels[i] + 0.587 * reference.pixels[i + 1] +
                     0.114 * reference.pixels[i + 2];
    lo = std::min(lo, y);
    hi = std::max(hi, y);
  }
  const Result<double> s = ssim(reference, test);
  ASSERT_TRUE(s.ok());
  EXPECT_GT(*s, luminanceTerm(lo, lo + d));
  EXPECT_LT(*s, luminanceTerm(hi, hi + d));
}

TEST(ImageMetrics, SsimFallsAsNoiseGrows) {
  const Image reference = texture(64, 48, 40, 215);
  double previous = 1.0;
  for (const int amplitude : {2, 8, 32}) {
    Image test = reference;
    for (int y = 0; y < test.height; ++y) {
      for (int x = 0; x < test.width; ++x) {
        const int sign = ((x * 7 + y * 3) % 5) < 2 ? 1 : -1;
        for (int c = 0; c < 3; ++c) channel(test, x, y, c) += sign * amplitude;
      }
    }
    const Result<double> s = ssim(reference, test);
    ASSERT_TRUE(s.ok());
    EXPECT_LT(*s, previous) << "amplitude " << amplitude;
    previous = *s;
  }
  EXPECT_LT(previous, 0.9);
}

TEST(ImageMetrics, SsimMapHoldsOneValuePerWholeWindowAndOnlyWindowsOverAChangeDrop) {
  const int w = 40, h = 30;
  const Image reference = texture(w, h);
  Image test = reference;
  set(test, 20, 15, {0, 0, 0});
  const Result<ScalarMap> map = ssimMap(reference, test);
  ASSERT_TRUE(map.ok()) << map.message();
  ASSERT_EQ(map->width, w - 10);
  ASSERT_EQ(map->height, h - 10);
  ASSERT_EQ(map->values.size(), std::size_t(30 * 20));
  // Value (x, y) is the window centred on (x + 5, y + 5): those over pixel (20, 15) are
  // x in [10, 20], y in [5, 15].
  for (int y = 0; y < map->height; ++y) {
    for (int x = 0; x < map->width; ++x) {
      const float v = map->values[static_cast<std::size_t>(y) * map->width + x];
      if (x >= 10 && x <= 20 && y >= 5 && y <= 15) {
        EXPECT_LT(v, 1.0f) << x << "," << y;
      } else {
        EXPECT_EQ(v, 1.0f) << x << "," << y;
      }
    }
  }
  const Result<double> s = ssim(reference, test);
  ASSERT_TRUE(s.ok());
  EXPECT_NEAR(meanOf(map->values), *s, 1e-6);
}

TEST(ImageMetrics, SsimNeedsAWholeElevenByElevenWindow) {
  EXPECT_FALSE(ssim(texture(10, 40), texture(10, 40)).ok());
  EXPECT_FALSE(ssim(texture(40, 10), texture(40, 10)).ok());
  const Result<ScalarMap> map = ssimMap(texture(11, 11), texture(11, 11));
  ASSERT_TRUE(map.ok()) << map.message();
  EXPECT_EQ(map->width, 1);
  EXPECT_EQ(map->height, 1);
}

// --- FLIP ------------------------------------------------------------------------------------

// A dark left part and a bright right part, the edge at column edgeX.
Image edgeImage(int w, int h, int edgeX) {
  Image image = solid(w, h, {40, 40, 40});
  for (int y = 0; y < h; ++y) {
    for (int x = edgeX; x < w; ++x) set(image, x, y, {220, 220, 220});
  }
  return image;
}

TEST(ImageMetrics, FlipGrowsWithTheShiftOfAnEdgeAndStaysZeroFarFromIt) {
  const int w = 96, h = 48;
  const Image reference = edgeImage(w, h, 48);
  const Result<double> one = flip(reference, edgeImage(w, h, 49));
  const Result<double> four = flip(reference, edgeImage(w, h, 52));
  ASSERT_TRUE(one.ok() && four.ok());
  EXPECT_GT(*one, 0.0);
  EXPECT_GT(*four, *one);
  // The filters reach ~10 pixels at 67 pixels per degree: far from the edge both images agree.
  const Result<std::vector<float>> map = flipMap(reference, edgeImage(w, h, 49));
  ASSERT_TRUE(map.ok());
  EXPECT_EQ((*map)[24 * w + 5], 0.0f);
  EXPECT_EQ((*map)[24 * w + 90], 0.0f);
  const auto row = map->begin() + 24 * w;
  const auto peak = std::max_element(row, row + w);
  EXPECT_GT(*peak, 0.3f);
  EXPECT_NEAR(peak - row, 48, 1);  // the error sits on the edge
}

TEST(ImageMetrics, FlipSeesAOnePixelShiftLessSharplyButWiderWithMorePixelsPerDegree) {
  // Farther away (more pixels per degree) the eye's filters span more pixels: a one-pixel shift
  // of an edge gives a lower peak error, spread over a wider band.
  const int w = 96;
  const Image reference = edgeImage(w, 48, 48);
  const Image shifted = edgeImage(w, 48, 49);
  const Result<std::vector<float>> near = flipMap(reference, shifted, 20.0);
  const Result<std::vector<float>> far = flipMap(reference, shifted, 120.0);
  ASSERT_TRUE(near.ok() && far.ok());
  const auto row = [&](const std::vector<float>& map) {
    return std::vector<float>(map.begin() + 24 * w, map.begin() + 25 * w);
  };
  const std::vector<float> n = row(*near), f = row(*far);
  EXPECT_GT(*std::max_element(n.begin(), n.end()), *std::max_element(f.begin(), f.end()));
  const auto band = [](const std::vector<float>& r) {
    return std::count_if(r.begin(), r.end(), [](float v) { return v > 0.01f; });
  };
  EXPECT_LT(band(n), band(f));
}

TEST(ImageMetrics, AColourChangeThatKeepsLumaIsInvisibleToSsimButNotToFlip) {
  // 0.299 * 199 + 0.587 * 93 + 0.114 * 122 = 128: the same Rec. 601 luma as grey 128.
  const Image grey = solid(32, 32, {128, 128, 128});
  Image test = grey;
  for (int y = 8; y < 24; ++y) {
    for (int x = 8; x < 24; ++x) set(test, x, y, {199, 93, 122});
  }
  const Result<double> s = ssim(grey, test);
  ASSERT_TRUE(s.ok());
  EXPECT_NEAR(*s, 1.0, 1e-12);
  const Result<double> f = flip(grey, test);
  ASSERT_TRUE(f.ok());
  EXPECT_GT(*f, 0.05);
  // And on flat images, where no edges or points exist, all of it comes from the colour pipeline.
  const Result<double> flat = flip(grey, solid(32, 32, {199, 93, 122}));
  ASSERT_TRUE(flat.ok());
  EXPECT_GT(*flat, 0.3);
}

// LDR-FLIP's colour pipeline on flat images (no features, filtering changes nothing), from the
// paper's formulas and the standard CIELAB values of the sRGB primaries (D65).
double flatFlip(double lightness1, double lightness2) {
  const auto hunt = [](double l, double a, double b) {
    return std::array{l, 0.01 * l * a, 0.01 * l * b};
  };
  const auto green = hunt(87.7350, -86.1827, 83.1793);
  const auto blue = hunt(32.2970, 79.1875, -107.8602);
  const double cmax = std::pow(
      std::abs(green[0] - blue[0]) + std::hypot(green[1] - blue[1], green[2] - blue[2]), 0.7);
  const double e = std::pow(std::abs(lightness1 - lightness2), 0.7);  // greys: a = b = 0
  const double pc = 0.4, pt = 0.95;
  return e < pc * cmax ? pt / (pc * cmax) * e
                       : pt + (e - pc * cmax) / (cmax - pc * cmax) * (1 - pt);
}

double greyLightness(int v) {
  const double c = v / 255.0;
  const double linear = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  return linear > std::pow(6.0 / 29.0, 3) ? 116.0 * std::cbrt(linear) - 16.0
                                          : linear * 116.0 / (3.0 * std::pow(6.0 / 29.0, 2));
}

TEST(ImageMetrics, FlipOfFlatGreysFollowsThePapersColourDifferenceAndRedistribution) {
  // Black against white: |dL| = 100, above p_c c_max (the compressed upper range).
  const Result<double> bw = flip(solid(24, 24, {0, 0, 0}), solid(24, 24, {255, 255, 255}));
  ASSERT_TRUE(bw.ok());
  EXPECT_NEAR(*bw, flatFlip(0.0, 100.0), 1e-3);
  EXPECT_GT(*bw, 0.95);
  // Two close greys: the linear lower range.
  const Result<double> close = flip(solid(24, 24, {128, 128, 128}), solid(24, 24, {134, 134, 134}));
  ASSERT_TRUE(close.ok());
  EXPECT_NEAR(*close, flatFlip(greyLightness(128), greyLightness(134)), 1e-3);
  EXPECT_LT(*close, 0.95);
}

double greyLinear(int v) {
  const double c = v / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

TEST(ImageMetrics, FlipOfAThinLineAtOnePixelPerDegreeFollowsThePapersFeatureFormula) {
  // At 1 pixel per degree every Gaussian of the paper is far narrower than a pixel: the contrast
  // sensitivity filters keep each pixel as it is, and the normalised detectors become the
  // stencils [1 0 -1] (edge) and [1/2 -1 1/2] (point). On grey 100 with a one-pixel line of grey
  // 160, the line's pixels then have Delta E_c of the two greys, no edge difference and a point
  // difference of the normalised achromatic step dY (the greys' linear luminances):
  // Delta E_f = (dY / sqrt(2))^q_f and Delta E = Delta E_c^(1 - Delta E_f).
  const int w = 16, h = 8, lineX = 7;
  const Image reference = solid(w, h, {100, 100, 100});
  Image test = reference;
  for (int y = 0; y < h; ++y) set(test, lineX, y, {160, 160, 160});
  const Result<std::vector<float>> map = flipMap(reference, test, 1.0);
  ASSERT_TRUE(map.ok()) << map.message();
  const double deltaEc = flatFlip(greyLightness(100), greyLightness(160));
  const double deltaEf = std::sqrt((greyLinear(160) - greyLinear(100)) / std::sqrt(2.0));
  for (int y = 0; y < h; ++y) {
    EXPECT_NEAR((*map)[y * w + lineX], std::pow(deltaEc, 1.0 - deltaEf), 1e-3) << y;
    // Beside the line the colours agree: Delta E_c = 0, whatever the edge detector sees.
    EXPECT_EQ((*map)[y * w + lineX - 1], 0.0f);
    EXPECT_EQ((*map)[y * w + lineX + 1], 0.0f);
  }
  // The feature term raises the colour error on the line.
  EXPECT_GT((*map)[lineX], deltaEc + 0.1);
}

TEST(ImageMetrics, FlipMapHoldsOneValueInUnitRangePerPixelAndItsMeanIsFlip) {
  const Image a = texture(50, 30);
  const Image b = texture(50, 30, 0, 255);
  const Result<std::vector<float>> map = flipMap(a, b);
  ASSERT_TRUE(map.ok()) << map.message();
  ASSERT_EQ(map->size(), std::size_t(50 * 30));
  for (float v : *map) {
    ASSERT_GE(v, 0.0f);
    ASSERT_LE(v, 1.0f);
  }
  const Result<double> f = flip(a, b);
  ASSERT_TRUE(f.ok());
  EXPECT_NEAR(meanOf(*map), *f, 1e-12);
  EXPECT_GT(*f, 0.0);
}

// --- Bad input -------------------------------------------------------------------------------

TEST(ImageMetrics, MismatchedEmptyOrMalformedImagesAreErrors) {
  const Image a = texture(20, 20);
  const Image wider = texture(21, 20);
  Image truncated = a;
  truncated.pixels.pop_back();
  const Image empty;
  for (const Image* b : std::initializer_list<const Image*>{&wider, &truncated, &empty}) {
    EXPECT_FALSE(psnr(a, *b).ok());
    EXPECT_FALSE(psnr(*b, a).ok());
    EXPECT_FALSE(ssim(a, *b).ok());
    EXPECT_FALSE(ssimMap(a, *b).ok());
    EXPECT_FALSE(flip(a, *b).ok());
    EXPECT_FALSE(flipMap(*b, a).ok());
  }
  EXPECT_FALSE(psnr(empty, empty).ok());
  const Result<double> r = psnr(a, wider);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("differ in size"), std::string::npos) << r.message();
}

TEST(ImageMetrics, FlipRejectsPixelsPerDegreeThatAreNotPositiveAndFinite) {
  const Image a = texture(20, 20);
  for (const double ppd : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    EXPECT_FALSE(flip(a, a, ppd).ok()) << ppd;
  }
  EXPECT_TRUE(flip(a, a, 0.5).ok());  // detectors narrower than a pixel see nothing, no NaN
  const Result<double> tiny = flip(a, texture(20, 20, 0, 255), 0.5);
  ASSERT_TRUE(tiny.ok());
  EXPECT_TRUE(std::isfinite(*tiny));
}

// --- Coverage --------------------------------------------------------------------------------

TEST(ImageMetrics, BackgroundMaskMarksPixelsBeyondTheTolerance) {
  Image image = solid(4, 1, {10, 20, 30});
  set(image, 1, 0, {12, 20, 30});  // 2 off in R
  set(image, 2, 0, {10, 20, 27});  // 3 off in B
  set(image, 3, 0, {200, 0, 90});  // geometry
  channel(image, 0, 0, 3) = 0;     // alpha does not count
  const Mask exact = backgroundMask(image, {10, 20, 30});
  EXPECT_EQ(exact.width, 4);
  EXPECT_EQ(exact.height, 1);
  EXPECT_EQ(exact.covered, (std::vector<std::uint8_t>{0, 1, 1, 1}));
  EXPECT_EQ(backgroundMask(image, {10, 20, 30}, 2).covered,
            (std::vector<std::uint8_t>{0, 0, 1, 1}));
  EXPECT_EQ(backgroundMask(image, {10, 20, 30}, 3).covered,
            (std::vector<std::uint8_t>{0, 0, 0, 1}));
  EXPECT_TRUE(backgroundMask(Image{}, {0, 0, 0}).covered.empty());
}

TEST(ImageMetrics, CoverageDifferenceCountsPixelsCoveredInExactlyOneMask) {
  const Mask reference{4, 2, {1, 1, 0, 0, 0, 1, 0, 0}};
  const Mask test{4, 2, {1, 0, 0, 1, 0, 2, 1, 0}};  // any non-zero byte is covered
  const Result<double> d = coverageDifference(reference, test);
  ASSERT_TRUE(d.ok()) << d.message();
  EXPECT_DOUBLE_EQ(*d, 3.0 / 8.0);  // pixels 1, 3 and 6
  EXPECT_DOUBLE_EQ(*coverageDifference(reference, reference), 0.0);
  const Mask complement{4, 2, {0, 0, 1, 1, 1, 0, 1, 1}};
  EXPECT_DOUBLE_EQ(*coverageDifference(reference, complement), 1.0);
}

TEST(ImageMetrics, CoverageDifferenceOfMismatchedOrMalformedMasksIsAnError) {
  const Mask a{4, 2, std::vector<std::uint8_t>(8, 1)};
  EXPECT_FALSE(coverageDifference(a, Mask{2, 4, std::vector<std::uint8_t>(8, 1)}).ok());
  EXPECT_FALSE(coverageDifference(a, Mask{4, 2, std::vector<std::uint8_t>(7, 1)}).ok());
  EXPECT_FALSE(coverageDifference(Mask{}, Mask{}).ok());
}

TEST(ImageMetrics, CoverageMapShowsHolesRedShardsCyanAndTheRestDimmed) {
  const Mask reference{3, 1, {1, 1, 0}};
  const Mask test{3, 1, {1, 0, 1}};
  const Image frame{3, 1, {200, 100, 50, 255, 7, 7, 7, 255, 9, 9, 9, 255}};
  const Result<Image> map = coverageMap(frame, reference, test);
  ASSERT_TRUE(map.ok()) << map.message();
  EXPECT_EQ(map->pixels, (std::vector<std::uint8_t>{100, 50, 25, 255,     // both: dimmed
                                                    255, 0, 0, 255,       // hole
                                                    0, 255, 255, 255}));  // shard
  EXPECT_FALSE(coverageMap(Image{2, 1, std::vector<std::uint8_t>(8, 0)}, reference, test).ok());
  EXPECT_FALSE(coverageMap(frame, reference, Mask{2, 1, {1, 1}}).ok());
}

// --- Heat map --------------------------------------------------------------------------------

TEST(ImageMetrics, ErrorHeatMapRunsFromDarkToBrightAndClampsOutOfRangeValues) {
  std::vector<float> values;
  for (int i = 0; i <= 20; ++i) values.push_back(i / 20.0f);
  values.push_back(-1.0f);
  values.push_back(5.0f);
  values.push_back(std::nanf(""));
  const int w = static_cast<int>(values.size());
  const Image map = errorHeatMap(values, w, 1);
  ASSERT_EQ(map.width, w);
  ASSERT_EQ(map.height, 1);
  ASSERT_EQ(map.pixels.size(), values.size() * 4);
  const auto px = [&](int i) {
    return std::array<int, 4>{map.pixels[i * 4], map.pixels[i * 4 + 1], map.pixels[i * 4 + 2],
                              map.pixels[i * 4 + 3]};
  };
  // Magma's ends: near-black for 0, pale yellow for 1.
  EXPECT_LE(px(0)[0] + px(0)[1] + px(0)[2], 10);
  EXPECT_GE(px(20)[0], 245);
  EXPECT_GE(px(20)[1], 245);
  EXPECT_GE(px(20)[2], 180);
  // Lightness rises with the error.
  double previous = -1.0;
  for (int i = 0; i <= 20; ++i) {
    const auto p = px(i);
    EXPECT_EQ(p[3], 255);
    const double luma = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
    EXPECT_GT(luma, previous) << i;
    previous = luma;
  }
  EXPECT_EQ(px(21), px(0));   // below 0 shows as 0
  EXPECT_EQ(px(22), px(20));  // above 1 as 1
  EXPECT_EQ(px(23), px(20));  // NaN as 1
  EXPECT_TRUE(errorHeatMap(values, w + 1, 1).empty());
  EXPECT_TRUE(errorHeatMap({}, 0, 0).empty());
}

// --- Pareto front ----------------------------------------------------------------------------

TEST(ImageMetrics, ParetoFrontKeepsTheNonDominatedPointsSortedByX) {
  const std::vector<std::pair<double, double>> points = {
      {1.0, 5.0},           // 0: front (lowest x)
      {2.0, 3.0},           // 1: front
      {2.0, 4.0},           // 2: same x as 1, worse y: dominated
      {3.0, 3.0},           // 3: same y as 1, worse x: dominated
      {4.0, 1.0},           // 4: front
      {2.0, 3.0},           // 5: duplicate of 1: only the first is listed
      {5.0, 5.0},           // 6: dominated by all of the front
      {0.5, std::nan("")},  // 7: NaN: never on the front
      {6.0, 0.5},           // 8: front (lowest y)
      {1.0, 5.0},           // 9: duplicate of 0
  };
  EXPECT_EQ(paretoFront(points), (std::vector<std::size_t>{0, 1, 4, 8}));
  EXPECT_TRUE(paretoFront({}).empty());
  const std::vector<std::pair<double, double>> one = {{3.0, 2.0}};
  EXPECT_EQ(paretoFront(one), (std::vector<std::size_t>{0}));
  // Listed in x order whatever the input order.
  const std::vector<std::pair<double, double>> reversed = {{6.0, 0.5}, {4.0, 1.0}, {1.0, 5.0}};
  EXPECT_EQ(paretoFront(reversed), (std::vector<std::size_t>{2, 1, 0}));
}

// --- Cost ------------------------------------------------------------------------------------

TEST(ImageMetrics, FlipAndSsimSeeAChangedNinthOfAFrameAsVisibleAndFarFromTotal) {
  // (Their time on a 640x360 frame: metrics_bench.)
  const test::FramePair p = test::frameWithAChangedNinth();
  const Result<double> f = flip(p.reference, p.test);
  const Result<double> s = ssim(p.reference, p.test);
  ASSERT_TRUE(f.ok() && s.ok());
  EXPECT_GT(*f, 0.02);
  EXPECT_LT(*f, 0.5);
  EXPECT_LT(*s, 0.99);
  EXPECT_GT(*s, 0.5);
}

}  // namespace
}  // namespace hlod::metrics
