#pragma once
// Sampling one linear piece of a piecewise-linear density: on t ∈ [0, 1] the density is
//   p(t) = (a (1 − t) + b t) / ((a + b) / 2),   a, b >= 0 the (unnormalised) end values,
// with CDF F(t) = t (2a (1 − t) + (a + b) t) / (a + b) — every term non-negative, so F is
// evaluated without cancellation.
//
// Inversion. F(t) = f is the quadratic (b − a) t² + 2a t − (a + b) f = 0. The textbook root
// (−a + √(a² + (b² − a²) f)) / (b − a) cancels catastrophically as b → a (0/0 at a = b), which is
// why pbrt-v4 and Mitsuba switch to the constant case below a threshold (|a − b| < 1e-4 (a + b))
// and lose precision just above it. Multiplying by the conjugate gives the same root as
//   t = f (a + b) / (a + √((1 − f) a² + f b²)),
// a quotient of non-negative sums: no cancellation anywhere, the constant limit (a = b: t = f)
// and the linear limits (a = 0: t = √f; b = 0: t = 1 − √(1 − f)) are exact cases of the formula,
// and the relative error is a few double ulps for every a, b. a and b are scaled by 1/max(a, b)
// first, so the squares neither overflow nor underflow whatever the magnitudes.
//
// Degenerate input: a + b = 0 (no mass) is treated as the uniform density (t = f, F(t) = t),
// so neither function ever returns NaN for finite non-negative arguments.

#include <algorithm>
#include <cmath>

namespace acdf {

// The t ∈ [0, 1] with F(t) = f, for f ∈ [0, 1] (clamped; NaN gives 0).
inline double sampleLinearSegment(double f, double a, double b) {
  if (!(f > 0.0)) return 0.0;
  f = std::min(f, 1.0);
  const double scale = std::max(a, b);
  if (!(scale > 0.0)) return f;
  a /= scale;
  b /= scale;
  const double t = f * (a + b) / (a + std::sqrt((1.0 - f) * a * a + f * b * b));
  return std::min(t, 1.0);
}

// F(t) for t ∈ [0, 1] (clamped; NaN gives 0): the inverse of sampleLinearSegment().
inline double linearSegmentCdf(double t, double a, double b) {
  if (!(t > 0.0)) return 0.0;
  t = std::min(t, 1.0);
  const double total = a + b;
  if (!(total > 0.0)) return t;
  return std::min(t * (2.0 * a * (1.0 - t) + total * t) / total, 1.0);
}

}  // namespace acdf
