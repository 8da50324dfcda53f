#pragma once
// An adaptive 1D CDF (Lawrence et al. 2005): the uniform table's CDF simplified to the grid
// vertices that matter, so the pdf is piecewise constant on non-uniform intervals.
//
// Storage: one float CDF value and one grid-vertex index (8-bit up to 255 cells, 16-bit up to
// 65535, else 32-bit) per kept point. Sampling inverts by binary search over the kept CDF values;
// pdf(x) finds x's interval by binary search over the kept vertices. Both use the same stored
// numbers, so they agree exactly.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/sample.h"
#include "acdf/sampling/simplify.h"
#include "acdf/sampling/vertex_indices.h"

namespace acdf {

class AdaptiveCdf1D {
 public:
  // Throws std::invalid_argument on an empty input, a bad value (naming its index), an invalid
  // domain or invalid options.
  explicit AdaptiveCdf1D(std::span<const float> function, float lo = 0.0f, float hi = 1.0f,
                         const SimplifyOptions& options = {});

  Sample1D sample(float u) const;
  float pdf(float x) const;  // 0 outside [lo, hi)
  float invert(float x) const;

  std::size_t points() const { return cdf_.size(); }  // kept breakpoints, ends included
  uint32_t vertex(std::size_t point) const { return vertices_[point]; }
  float cdfAt(std::size_t point) const { return cdf_[point]; }
  const GridAxis& axis() const { return axis_; }
  double integral() const { return integral_; }
  bool isUniformFallback() const { return integral_ == 0.0; }
  std::size_t bytes() const { return cdf_.size() * sizeof(float) + vertices_.bytes(); }

 private:
  GridAxis axis_;
  double integral_;
  std::vector<float> cdf_;
  VertexIndices vertices_;
};

}  // namespace acdf
