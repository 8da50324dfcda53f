#pragma once
// Vose's alias method: O(1) sampling of a discrete distribution over n cells (AliasTable), and
// the continuous piecewise-constant distribution over [lo, hi) it induces, uniform within the
// chosen cell (AliasTable1D).
//
// Precision: built in double; stores per cell the acceptance probability (float), the alias
// (uint32) and the cell's probability (float, returned as the pdf): 12 bytes a cell.
// A continuous sample uses one variate for both the cell and its position inside it, so the
// position has 24 - log2(n) bits of resolution; use a second variate where that matters.
// Zero mass: cells of probability 0 are never returned; an all-zero input is uniform.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/sample.h"

namespace acdf {

class AliasTable {
 public:
  struct Discrete {
    uint32_t index = 0;
    float probability = 0;  // > 0
    float remapped = 0;     // the variate's unused fraction, uniform in [0,1), for reuse
  };

  // Throws std::invalid_argument on an empty input, more than 2^32-1 cells, or a negative, NaN or
  // Inf weight (naming the first bad index).
  explicit AliasTable(std::span<const float> weights);

  Discrete sample(float u) const;
  float probability(uint32_t index) const { return cells_[index].probability; }

  std::size_t size() const { return cells_.size(); }
  double integral() const { return integral_; }  // Σ weights (double)
  bool isUniformFallback() const { return integral_ == 0.0; }
  std::size_t bytes() const { return cells_.size() * sizeof(Cell); }

 private:
  struct Cell {
    float accept;       // keep this cell if the variate's fraction is below it
    float probability;  // normalised probability of the cell
    uint32_t alias;
  };
  double integral_ = 0;
  std::vector<Cell> cells_;
};

class AliasTable1D {
 public:
  explicit AliasTable1D(std::span<const float> function, float lo = 0.0f, float hi = 1.0f);

  Sample1D sample(float u) const;
  float pdf(float x) const;  // 0 outside [lo, hi)

  std::size_t size() const { return table_.size(); }
  const GridAxis& axis() const { return axis_; }
  const AliasTable& table() const { return table_; }
  double integral() const { return table_.integral() * axis_.cellWidth(); }  // ∫ f dx
  bool isUniformFallback() const { return table_.isUniformFallback(); }
  std::size_t bytes() const { return table_.bytes(); }

 private:
  GridAxis axis_;
  AliasTable table_;
};

}  // namespace acdf
