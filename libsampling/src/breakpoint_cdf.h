#pragma once
// Internal: the one piece of code that samples, evaluates and inverts a piecewise-linear CDF whose
// breakpoints sit on grid vertices. PiecewiseConstant1D (every vertex), AdaptiveCdf1D (kept
// vertices) and each level of a Cascade (pooled 1D CDFs) are all views of this.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/vertex_indices.h"

namespace acdf::detail {

// std::upper_bound(values, values + n, u) − values for non-decreasing values, without its
// data-dependent branches: the trip count depends on n alone and each step is a conditional move,
// so a sample costs no mispredictions (about half of its steps would be, on random u).
inline std::size_t upperBound(const float* values, std::size_t n, float u) {
  if (n == 0) return 0;
  const float* base = values;
  while (n > 1) {
    const std::size_t half = n / 2;
    // !(u < v) rather than v <= u: upper_bound's own test, so a NaN u ends where it does.
    base = !(u < base[half]) ? base + half : base;
    n -= half;
  }
  return static_cast<std::size_t>(base - values) + !(u < *base);
}

// The end points of every CDF are implicit: value 0 at vertex 0 and value 1 at vertex `cells`.
// Only the interior points are stored, which for the many short conditional CDFs of a cascade is
// most of its storage (a CDF of two intervals stores one value and one index, not three of each).
struct BreakpointCdf {
  const float* interior = nullptr;  // count − 2 values in [0, 1], non-decreasing
  std::size_t count = 0;            // points, end points included (>= 2)
  uint32_t cells = 0;               // grid cells of the axis: the vertex of the last point
  // Grid vertex of interior point j is (*vertices)[vertexOffset + j − 1]; null means point j is
  // vertex j (every vertex is a point).
  const VertexIndices* vertices = nullptr;
  std::size_t vertexOffset = 0;

  // The accessors below are a few instructions each and sit on every sample and pdf; they are
  // forced inline because in a large translation unit (cascade.cpp) GCC reaches its unit-growth
  // limit and leaves them as calls, whose spills and argument copies cost more than their bodies.
  [[gnu::always_inline]] float value(std::size_t j) const { return j + 1 == count ? 1.0f : values(j)[0]; }

  // {value(j), value(j + 1)} for an interval j < count − 1.
  [[gnu::always_inline]] std::array<float, 2> values(std::size_t j) const {
    return {j == 0 ? 0.0f : interior[j - 1], j + 2 == count ? 1.0f : interior[j]};
  }

  [[gnu::always_inline]] uint32_t vertex(std::size_t j) const { return j + 1 == count ? cells : ends(j)[0]; }

  // {vertex(j), vertex(j + 1)} for an interval j < count − 1.
  [[gnu::always_inline]] std::array<uint32_t, 2> ends(std::size_t j) const {
    if (!vertices) return {static_cast<uint32_t>(j), static_cast<uint32_t>(j + 1)};
    const std::size_t next = vertexOffset + j;  // the index of interior point j + 1
    return {j == 0 ? 0u : (*vertices)[next - 1], j + 2 == count ? cells : (*vertices)[next]};
  }

  // The interval j with value(j) <= u < value(j+1), for u in [0, 1): it always has positive mass.
  [[gnu::always_inline]] std::size_t intervalOfVariate(float u) const { return upperBound(interior, count - 2, u); }

  // The interval holding `cell`: the number of interior vertices at or below it.
  [[gnu::always_inline]] std::size_t intervalOfCell(uint32_t cell) const {
    if (!vertices) return std::min<std::size_t>(cell, count - 2);
    return vertices->countAtMost(vertexOffset, vertexOffset + count - 2, cell);
  }

  // Exact in double: the difference of two floats.
  [[gnu::always_inline]] double mass(std::size_t j) const {
    const auto [lo, hi] = values(j);
    return static_cast<double>(hi) - static_cast<double>(lo);
  }
};

// One sampled coordinate: the interval chosen, where in it the sample fell (the coordinate, its
// cell and grid coordinate), and the density along this axis.
struct Draw {
  std::size_t interval;
  GridAxis::Placed placed;
  double density;
};

inline Draw draw(const BreakpointCdf& c, const GridAxis& axis, float u) {
  const std::size_t j = c.intervalOfVariate(u);
  const auto [lo, hi] = c.values(j);
  const double mass = static_cast<double>(hi) - static_cast<double>(lo);
  const auto [first, end] = c.ends(j);
  const double t = (static_cast<double>(u) - lo) / mass;
  return {j, axis.placeOnGrid(first, end, t), axis.density(mass, end - first)};
}

struct Lookup {
  std::size_t interval;
  double density;  // 0 where the CDF has no mass
};

// The interval holding grid cell `cell` of the axis and its density there.
inline Lookup lookupCell(const BreakpointCdf& c, const GridAxis& axis, uint32_t cell) {
  const std::size_t j = c.intervalOfCell(cell);
  const auto [first, end] = c.ends(j);
  return {j, axis.density(c.mass(j), end - first)};
}

inline Lookup lookup(const BreakpointCdf& c, const GridAxis& axis, float x) {
  return lookupCell(c, axis, axis.cellOf(x));
}

inline float invert(const BreakpointCdf& c, const GridAxis& axis, float x) {
  const std::size_t j = c.intervalOfCell(axis.cellOf(x));
  const auto [first, end] = c.ends(j);
  const double t = std::clamp((axis.gridCoordinate(x) - first) / (end - first), 0.0, 1.0);
  return static_cast<float>(c.value(j) + t * c.mass(j));
}

// Appends the n+1 values of the normalised CDF of `masses` to `out` and returns Σ masses.
// Sums in double; the last value is exactly 1. Zero total mass gives the uniform CDF k/n.
//
// Every cell of positive mass gets a positive float step, so its pdf is never 0: rounding each
// prefix sum to float alone would give a cell below the CDF's resolution there (6e-8 near F = 1)
// a step of 0, leaving mass no sample can reach and biasing an estimator that uses this table
// alone. Where rounding left such a step, the values after it are raised to the next float, and a
// backward pass from the exact 1 lowers values where that ran into the end, so each positive cell
// keeps at least one ulp of F. A zero-mass cell keeps a step of exactly 0. The cost: a cell's
// probability is off by at most a few ulps of F (absolute), as rounding alone makes it; tiny
// cells now err upwards instead of to 0.
template <class T>
double appendCdf(std::span<const T> masses, std::vector<float>& out) {
  double total = 0.0;
  for (T m : masses) total += static_cast<double>(m);
  const std::size_t n = masses.size(), first = out.size();
  out.push_back(0.0f);
  double prefix = 0.0;
  for (std::size_t k = 1; k < n; ++k) {
    prefix += static_cast<double>(masses[k - 1]);
    float value = static_cast<float>(total > 0.0 ? prefix / total : static_cast<double>(k) / n);
    value = std::max(value, out.back());  // an earlier value may have been raised
    if (masses[k - 1] > 0 && value == out.back()) value = std::nextafter(value, 2.0f);
    out.push_back(value);
  }
  out.push_back(1.0f);
  if (total > 0.0) {
    float* cdf = out.data() + first;
    for (std::size_t k = n - 1; k >= 1; --k) {
      const float limit = masses[k] > 0 ? std::nextafter(cdf[k + 1], 0.0f) : cdf[k + 1];
      if (cdf[k] <= limit) break;  // the values below were not raised past their limits either
      cdf[k] = limit;
    }
  }
  return total;
}

}  // namespace acdf::detail
