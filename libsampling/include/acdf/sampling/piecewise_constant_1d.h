#pragma once
// The classic tabulated 1D distribution (the baseline pbrt and Mitsuba use): a function given on
// n equal cells over [lo, hi), sampled by inverting its piecewise-linear CDF.
//
// Precision: cell masses are summed in double, normalised, and the CDF stored as n+1 floats.
// The pdf is derived from the stored CDF (ΔF / cell width), never from a separate copy of the
// function, so sample() and pdf() describe exactly the same distribution.
// Zero mass: an all-zero function gives the uniform distribution and isUniformFallback().

#include <cstddef>
#include <span>
#include <vector>

#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/sample.h"

namespace acdf {

class PiecewiseConstant1D {
 public:
  // Throws std::invalid_argument on an empty input or a negative, NaN or Inf value (naming the
  // first bad index), or an invalid domain.
  explicit PiecewiseConstant1D(std::span<const float> function, float lo = 0.0f, float hi = 1.0f);

  Sample1D sample(float u) const;
  // sample() of a distribution kept elsewhere as its cdf() and axis(): lets a caller hold many
  // distributions' CDFs in one array.
  static Sample1D sample(std::span<const float> cdf, const GridAxis& axis, float u);
  float pdf(float x) const;  // 0 outside [lo, hi)
  float invert(float x) const;

  std::size_t size() const { return axis_.cells(); }
  const GridAxis& axis() const { return axis_; }
  double integral() const { return integral_; }  // ∫ f over the domain (double sum)
  bool isUniformFallback() const { return integral_ == 0.0; }
  std::span<const float> cdf() const { return cdf_; }
  std::size_t bytes() const { return cdf_.size() * sizeof(float); }

 private:
  GridAxis axis_;
  double integral_;
  std::vector<float> cdf_;
};

}  // namespace acdf
