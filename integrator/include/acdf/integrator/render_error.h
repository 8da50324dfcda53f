#pragma once
// A render's error against a reference image (same size, RGB), as `acdf bench-error` reports it:
// relMSE = mean over pixels and channels of (I − R)² / (R² + 0.01), the offset keeping black
// reference pixels from dominating the mean, and RMSE = √(mean of (I − R)²). Sums in double.

#include "acdf/envmap/image_file.h"

namespace acdf {

// The offset of relMSE's denominator.
inline constexpr double kRelMseOffset = 0.01;

struct RenderError {
  double relMse = 0, rmse = 0;
};

// `image` and `reference` must have the same size and channels.
RenderError renderError(const Image& image, const Image& reference);

// A false-colour picture of where `a` differs from `b` relative to `reference` (all RGB, of one
// size): red by the √ of the pixel's relMSE term (full red at a relative difference of 0.5), over
// a dim grey copy of the reference for orientation.
Image differenceImage(const Image& a, const Image& b, const Image& reference);

}  // namespace acdf
