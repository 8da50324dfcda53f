#pragma once
// A bilinear ("piecewise-linear") distribution on the unit square, optionally conditioned on
// parameters: the warp of the RGL measured materials (Dupuy & Jakob 2018, "An Adaptive
// Parameterization for Efficient Material Acquisition and Rendering" — the luminance and
// visible-NDF tables of a `.bsdf` file), as pbrt-v4's PiecewiseLinear2D and Mitsuba 3's
// Marginal2D<…, Continuous = true> define it.
//
// Density. Values are given on a rows × columns grid of *vertices*, vertex (r, c) at
// x = (r / (rows − 1), c / (columns − 1)); the density is their bilinear interpolation, normalised
// to integrate to 1 over [0, 1]². x[0] runs along rows (axes()[0]: rows − 1 cells) and x[1] along
// columns (axes()[1]), as everywhere in libsampling (axis 0 varies slowest). pbrt's and
// Mitsuba's point (x, y) is our (x[1], x[0]), and their variates (u.x, u.y) are our (u[1], u[0]).
//
// Parameters. With N >= 1 parameters, each has its own strictly increasing list of values and
// there is one vertex grid ("slice") per combination: values are laid out
// n_0 × … × n_{N−1} × rows × columns, row-major (the RGL luminance table is φi × θi × 32 × 32).
// Each slice is normalised on its own. At a parameter point p the distribution is the
// multilinear blend of the 2^N neighbouring slices: along each parameter the interval
// v_i <= p < v_{i+1} and weight α = (p − v_i) / (v_{i+1} − v_i) clamped to [0, 1] (so p outside
// the list takes the end slice; NaN takes the first; a one-value list always takes it). All the
// tables below are linear in the slice's density, so blending the slices' CDFs is exactly the
// CDF of the blended density: the CDFs are built per slice and blended at query time (only the
// corners of non-zero weight are read; on a grid point that is one slice).
//
// Sampling. u[0] picks the row strip: the marginal density over x[0] is linear between vertex
// rows (the row masses T_r = ∫ f(x[0] = r/(rows − 1), x[1]) dx[1]), so after a binary search of
// the marginal CDF the position inside the strip solves one quadratic (linear_segment.h, stable
// for every pair of end values). Within the strip, at the sampled x[0], the conditional density
// over x[1] is the lerp of the two vertex rows, its CDF the lerp of their CDFs (weighted by
// their masses); u[1] picks a column the same way and solves the quadratic of that cell.
//
// Storage, per slice (float): the normalised vertex densities (rows × columns), one normalised
// CDF over columns per vertex row (rows × columns), the row masses (rows) and the marginal CDF
// over rows (rows); plus the parameter values. bytes() reports it.
//
// Precision. Built in double from the input, stored as float; every query runs in double
// (parameter weights, blends, searches, quadratics) and rounds only the returned coordinates and
// density to float.
// - The CDFs are built by appendCdf (breakpoint_cdf.h): each row strip, and each cell of a
//   vertex row, with positive mass keeps a positive float step, and a positive vertex value whose
//   normalised density would underflow float is stored as the smallest denormal, never 0. So
//   pdf > 0 wherever the bilinear density is > 0. Blending (two vertex rows on a line, slices
//   between parameter values) sums in double: a cell or strip whose share of the blend is below
//   double resolution (≈ 1e-16, e.g. a row of 1 next to a row of 1e30) keeps pdf > 0 but gets no
//   step of the blended CDF, so it is not sampled.
// - The pdf is the density of the law sample() draws, computed from the stored CDF steps (row
//   interval probability × linear shape × column interval probability × linear shape), as
//   PiecewiseConstant1D derives its pdf from its CDF — not a second copy of the function. It
//   equals the bilinear interpolation of the normalised values up to the float rounding of the
//   stored CDFs: relative ≲ 2^-24 / P for an interval of probability P (a few 1e-7 on realistic
//   tables), more only for intervals below the CDF's resolution, which report the one-ulp
//   probability they are sampled with.
// - sample() evaluates its density at the returned float coordinates with the code pdf() runs,
//   so pdf(p, sample(p, u).x) == sample(p, u).pdf bit for bit. The quadratic's root has a relative
//   error of a few double ulps (the tests measure ≤ 2.2e-16 absolute against a brute-force
//   inversion); what limits invert(sample(u)) ≈ u is the float coordinate, |Δu| ≲ density ×
//   ulp(x) / 2 plus the rounding of u: 6e-8 to 4e-7 on the test tables.
// - Samples lie strictly inside (0, 1)², inside the cell whose density they report, with a
//   finite density > 0, for every u ∈ [0, 1)² (0 and kOneMinusEpsilon included; u is clamped
//   into that range, NaN to 0). A sample that would land exactly on a vertex line of zero
//   density is moved one float into its cell. pdf() is 0 outside [0, 1)² and where the blended
//   density has no mass.
//
// Zero mass: a slice whose values are all 0 is sampled uniformly (density 1) and reported by
// isUniformFallback(slice); blended with its neighbours it contributes that uniform density.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/sample.h"

namespace acdf {

class Bilinear2D {
 public:
  // Conditioning parameters plus the two sampled coordinates stay within kMaxDims.
  static constexpr std::size_t kMaxParameters = kMaxDims - 2;

  // values: Π n_p × rows × columns vertex values, row-major (see above); parameterValues: one
  // list per parameter. Throws std::invalid_argument naming the problem and its index unless
  // rows, columns >= 2, at most kMaxParameters parameters, each list non-empty, finite and
  // strictly increasing, values.size() matches, and every value is finite and >= 0.
  Bilinear2D(std::span<const float> values, uint32_t rows, uint32_t columns,
             std::vector<std::vector<float>> parameterValues = {});

  // params: parameters() values, first, as a Cascade's condition; u: 2 variates in [0, 1) (u[0]
  // rows, u[1] columns).
  SampleND sample(std::span<const float> params, std::span<const float> u) const;
  // Density w.r.t. area on [0, 1]² at x (x[0] rows, x[1] columns); 0 outside [0, 1)².
  float pdf(std::span<const float> params, std::span<const float> x) const;
  // The variates sample() maps to x (up to float rounding; x is clamped into the domain).
  std::array<float, 2> invert(std::span<const float> params, std::span<const float> x) const;
  // Shorthands without parameters.
  SampleND sample(std::span<const float> u) const { return sample({}, u); }
  float pdf(std::span<const float> x) const { return pdf({}, x); }
  std::array<float, 2> invert(std::span<const float> x) const { return invert({}, x); }

  uint32_t rows() const { return rows_; }
  uint32_t columns() const { return columns_; }
  // The sampled axes: rows − 1 and columns − 1 cells (the bilinear patches) over [0, 1).
  const std::vector<GridAxis>& axes() const { return axes_; }
  std::size_t parameters() const { return parameterValues_.size(); }
  const std::vector<float>& parameterValues(std::size_t parameter) const { return parameterValues_[parameter]; }
  std::size_t slices() const { return uniformFallback_.size(); }
  bool isUniformFallback(std::size_t slice) const { return uniformFallback_[slice] != 0; }
  std::size_t uniformFallbackSlices() const;
  std::size_t bytes() const;
  // The stored tables (Storage above), for sampling them in other arithmetic: slice s (row-major
  // over the parameters' values, the last varying fastest) at s × sliceFloats(); inside it the
  // densities at 0, the rows' column CDFs at rowCdfOffset(), the row masses at rowMassOffset()
  // and the marginal CDF at marginalOffset().
  std::span<const float> table() const { return table_; }
  std::size_t sliceFloats() const { return sliceFloats_; }
  std::size_t rowCdfOffset() const { return rowCdfOffset_; }
  std::size_t rowMassOffset() const { return rowMassOffset_; }
  std::size_t marginalOffset() const { return marginalOffset_; }

 private:
  struct Blend;  // the slices a parameter point reads, with their weights
  struct Strip;  // the conditional over columns at one x[0] inside a row strip
  Blend blend(std::span<const float> params) const;
  double marginal(const Blend& blend, uint32_t row) const;
  double stripMass(const Blend& blend, uint32_t row) const;
  double rowMass(const Blend& blend, uint32_t row) const;
  Strip strip(const Blend& blend, uint32_t row, double down) const;
  bool buildSlice(std::span<const float> values, float* out);

  uint32_t rows_, columns_;
  std::vector<GridAxis> axes_;
  std::vector<std::vector<float>> parameterValues_;
  std::vector<std::size_t> parameterStrides_;  // slices between consecutive values of a parameter
  // Offsets inside a slice's block of table_, and the block's size.
  std::size_t rowCdfOffset_, rowMassOffset_, marginalOffset_, sliceFloats_;
  std::vector<float> table_;
  std::vector<uint8_t> uniformFallback_;
};

}  // namespace acdf
