#pragma once
// A render's error against a reference image (same size, RGB), as `acdf bench-error` reports it:
// relMSE = mean over pixels and channels of (I − R)² / (R² + 0.01), the offset keeping black
// reference pixels from dominating the mean, and RMSE = √(mean of (I − R)²). Sums in double.
//
// Fireflies (a few pixels hit by a rare, huge sample) make relMSE jump between seeds. The
// trimmed relMSE is firefly-robust: a pixel's error is the mean over its channels of the relMSE
// term, the ⌊0.001 × pixels⌋ pixels of largest error are discarded, and the rest are averaged.

#include <cstdint>
#include <span>

#include "acdf/envmap/image_file.h"

namespace acdf {

// The offset of relMSE's denominator.
inline constexpr double kRelMseOffset = 0.01;
// The fraction of pixels (those of largest error) the trimmed relMSE leaves out.
inline constexpr double kTrimmedFraction = 0.001;

struct RenderError {
  double relMse = 0, rmse = 0, relMseTrimmed = 0;
};

// `image` and `reference` must have the same size and channels.
RenderError renderError(const Image& image, const Image& reference);

// A mean over independent seeds and its standard error s / √K (s the sample standard
// deviation); the error is 0 for a single seed, which cannot estimate it.
struct MeanAndError {
  double mean = 0, standardError = 0;
};
MeanAndError meanAndError(std::span<const double> values);

// One seed's render of a row: its error and its render time.
struct SeedRender {
  RenderError error;
  double seconds = 0;
};

// A row's figures over its seeds. Efficiency = 1 / (relMSE × seconds) of the means, its error by
// the delta method: (σ_E / E)² = (σ_r / r)² + (σ_t / t)² + 2 cov(r, t) / (K r t), with σ the
// standard errors of the means r, t and cov the seeds' sample covariance (render time and error
// go together under a time budget).
struct SeedAggregate {
  MeanAndError relMse, relMseTrimmed, rmse, seconds, efficiency;
};
// `seeds` must not be empty.
SeedAggregate aggregateSeeds(std::span<const SeedRender> seeds);

// One budget of a strategy's error-against-time curve: the means over seeds.
struct ErrorAtTime {
  double seconds = 0;
  MeanAndError relMse;
};

// The render time at which a strategy's relMSE reaches `target`, read off its curve (`points` in
// order of time; those without a positive time and relMSE are ignored). In log-log coordinates
// (x = ln t, y = ln relMSE) between the first two consecutive points whose relMSE falls across
// the target:
//   x* = x₁ + w (x₂ − x₁),  w = (ln target − y₁) / (y₂ − y₁),
// and its standard error from the points' relative errors δᵢ = σᵢ / relMSEᵢ (the errors of yᵢ):
//   σ_t / t* = √(((1 − w) δ₁)² + (w δ₂)²) / |slope|,  slope = (y₂ − y₁) / (x₂ − x₁).
// Where the curve does not cross the target, t* is extrapolated from the first point if it is
// already below the target, else from the last (still above it), by relMSE ∝ 1 / t:
//   t* = t · relMSE / target, σ_t / t* = δ; `extrapolated` says so. NaN without usable points.
struct TimeToTarget {
  double seconds = 0, standardError = 0;
  bool extrapolated = false;
};
TimeToTarget timeToReach(std::span<const ErrorAtTime> points, double target);

// A false-colour picture of where `a` differs from `b` relative to `reference` (all RGB, of one
// size): red by the √ of the pixel's relMSE term (full red at a relative difference of 0.5), over
// a dim grey copy of the reference for orientation.
Image differenceImage(const Image& a, const Image& b, const Image& reference);

}  // namespace acdf
