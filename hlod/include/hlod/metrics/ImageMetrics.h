#pragma once
// Image error of a frame against a full-detail reference frame: PSNR, SSIM (Wang et al. 2004),
// LDR-FLIP (Andersson et al. 2020), geometry coverage, a heat map of a per-pixel error for a
// report strip, and the Pareto front of (cost, error) points.
//
// Inputs are hlod::Image (8-bit sRGB RGBA, row 0 at the top); alpha is ignored by every metric.
// Two images compared must have equal, non-zero sizes and width * height * 4 bytes: anything else
// is an Error (bad input, checked once here), never a crash.
//
// Luma, where a metric works on one channel (SSIM): Rec. 601 Y' = 0.299 R + 0.587 G + 0.114 B on
// the 8-bit (gamma-encoded) values, in double precision and not rounded to an integer, so that a
// luma of 0..255 pairs with SSIM's dynamic range L = 255.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/Result.h"

namespace hlod::metrics {

// PSNR in dB over the R, G and B values (alpha ignored), peak 255: 10 log10(255^2 / MSE) with
// the MSE over all 3 * width * height values. +infinity when the images are identical.
Result<double> psnr(const Image& reference, const Image& test);

// Mean SSIM on luma, exactly as Wang, Bovik, Sheikh, Simoncelli, "Image Quality Assessment: From
// Error Visibility to Structural Similarity" (IEEE TIP 2004): 11x11 Gaussian window (sigma 1.5,
// normalised), K1 = 0.01, K2 = 0.03, L = 255. Borders as the authors' ssim_index.m ('valid'
// filtering): only windows that lie wholly inside the image count, so the images must be at least
// 11x11 (an Error otherwise). No downsampling. Exactly 1 for identical images.
Result<double> ssim(const Image& reference, const Image& test);

// A map of per-window values: width x height floats, row 0 at the top.
struct ScalarMap {
  int width = 0;
  int height = 0;
  std::vector<float> values;
};

// The SSIM of each window of ssim() (its mean is ssim()): (W - 10) x (H - 10) values, value
// (x, y) belonging to the window centred on pixel (x + 5, y + 5).
Result<ScalarMap> ssimMap(const Image& reference, const Image& test);

// Mean LDR-FLIP error (Andersson et al., "FLIP: A Difference Evaluator for Alternating Images",
// HPG 2020) for a viewer at pixelsPerDegree (67: 0.7 m from a 0.7 m wide 3840-pixel monitor).
// 0 for identical images; in [0, 1]. pixelsPerDegree must be finite and positive (an Error
// otherwise).
Result<double> flip(const Image& reference, const Image& test, double pixelsPerDegree = 67.0);

// The per-pixel LDR-FLIP error behind flip(): width * height values in [0, 1], row 0 at the top.
Result<std::vector<float>> flipMap(const Image& reference, const Image& test,
                                   double pixelsPerDegree = 67.0);

// Coverage: which pixels show geometry. covered holds width * height bytes, 0 for background and
// 1 for covered (any non-zero byte counts as covered where a mask is read).
struct Mask {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> covered;
};

// covered = the pixel's R, G or B differs from background by more than tolerance (alpha
// ignored). An empty or malformed image gives an empty mask (0 x 0).
Mask backgroundMask(const Image& image, std::array<std::uint8_t, 3> background, int tolerance = 0);

// The fraction of pixels covered in exactly one of the two masks (0: same silhouette, 1: the
// masks are complements). Masks must have equal, non-zero sizes and width * height bytes.
Result<double> coverageDifference(const Mask& reference, const Mask& test);

// Where two silhouettes differ, over the test frame dimmed to half: red where the reference shows
// geometry and the test frame does not (a hole: sky or the underside shows through), cyan where
// the test frame shows geometry that the reference does not (a shard). Same rules as
// coverageDifference for the masks; the frame must be their size.
Result<Image> coverageMap(const Image& frame, const Mask& reference, const Mask& test);

// A heat map of perPixel (width * height values, row 0 at the top) through matplotlib's magma
// colour map (perceptually uniform: black-purple for 0 to pale yellow for 1). Values are clamped
// to [0, 1]; NaN shows as 1. Opaque. A perPixel of the wrong size or a non-positive size gives an
// empty Image.
Image errorHeatMap(const std::vector<float>& perPixel, int width, int height);

// The Pareto front of points whose two coordinates are both better when lower (e.g. frame ms
// and an image error: FLIP, or -PSNR): the indices of the points that no other point dominates
// (no worse in both and better in one), sorted by x (and so by falling y). Of identical points
// only the first (lowest index) is listed; a point with a NaN coordinate is never on the front.
std::vector<std::size_t> paretoFront(std::span<const std::pair<double, double>> points);

}  // namespace hlod::metrics
