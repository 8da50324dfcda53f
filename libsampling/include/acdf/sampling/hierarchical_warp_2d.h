#pragma once
// Hierarchical sample warping over a 2D grid (Clarberg et al. 2005, "Wavelet importance sampling";
// the idea behind Mitsuba 3's Hierarchical2D): a mip-map pyramid of the cell masses, descended
// from its 1 × 1 top to the grid by splitting the variates, so that the map u → x is piecewise
// affine and keeps the variates' stratification (nearby u, nearby x) — unlike an alias table,
// which scatters neighbouring variates over unrelated cells.
//
// Pyramid. Level 0 is the grid (rows × columns); level k + 1 has ⌈rows_k / 2⌉ × ⌈columns_k / 2⌉
// nodes, each the sum of its 2 × 2 children on level k. Sizes that are not powers of two are not
// padded as a whole: a node on an odd edge simply has fewer children, the missing ones stored as
// zero mass in its block (so memory stays ≈ 4/3 of the grid, plus the odd edges). A node's four
// children are stored together (top-left, top-right, bottom-left, bottom-right), so each step of
// the descent reads one 16-byte block.
//
// Descent. At a node with child masses a b / c d: u0 picks the top row with probability
// pTop = (a + b) / (a + b + c + d) and is rescaled to [0, 1) inside the chosen interval
// (u0 / pTop or (u0 − pTop) / pBottom); then u1 picks the left column of the chosen row with
// probability a / (a + b) (or c / (c + d)) and is rescaled the same way. A missing row or column
// has probability 0 and is never chosen (the tests are u < p with u ∈ [0, 1)). At the grid the
// remaining u0, u1 are the position inside the cell.
//
// Precision. Masses are summed in double and stored as float, normalised so the top is 1 (no
// overflow for large values). Each level is summed from the stored floats of the level below, so
// a node's mass is 0 exactly when all its cells are: the descent never enters a node it cannot
// leave. A cell whose share underflows float (< 1.4e-45) has probability 0. The descent runs in
// double: each step rescales u by 1/p(branch), multiplying the absolute rounding error by the
// same factor, so after descending to a cell of probability P along an axis the error is
// ≈ 2^-53 / P of the cell — 2^-41 for an average column of a 4096-wide grid, where float
// arithmetic would add ≈ 2^-24 / P = 2^-12 of a cell, as much as the variate's own resolution
// (the tests measure the round trip u → cell → u: 2e-7 with float arithmetic, < 1e-9 in double,
// at 2048 × 4096). What is left is the variate's own information: a float variate carries 24
// bits, the path spends log2(1/P) of them, so an average cell of a 4096 × 2048 grid keeps 12 bits
// for its column position and 13 for its row; sampleCell() takes double variates for callers
// that have more.
//
// pdf. A cell's probability is its stored (normalised, float) leaf mass, read the same way by
// sample() and pdf(), so they agree bit for bit; the descent's branch probabilities are ratios of
// stored floats, so the law actually sampled differs from it by ≲ levels × 2^-24 relative.
//
// Zero mass: an all-zero grid is sampled uniformly and reports isUniformFallback().

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/sample.h"

namespace acdf {

class HierarchicalWarp2D {
 public:
  // values: axes[0].cells() rows × axes[1].cells() columns, row-major. Throws
  // std::invalid_argument unless there are exactly two axes matching values.size(), or for a
  // negative, NaN or Inf value (naming its cell).
  HierarchicalWarp2D(std::span<const float> values, std::vector<GridAxis> axes);

  struct CellSample {
    uint32_t row = 0, column = 0;
    double fractionDown = 0, fractionRight = 0;  // position inside the cell, in [0, 1)
    double probability = 0;                      // of the cell, > 0
  };
  // The descent itself, in double: u0 chooses rows, u1 columns (clamped into [0, 1)).
  CellSample sampleCell(double u0, double u1) const;
  // The variates sampleCell() maps to the given position inside the cell (0 for a cell of
  // probability 0, which sampleCell() never returns).
  std::array<double, 2> invertCell(uint32_t row, uint32_t column, double fractionDown, double fractionRight) const;
  double probability(uint32_t row, uint32_t column) const { return leaf(row, column); }

  // The libsampling interface on the axes' domain (x[0] along axes[0], x[1] along axes[1]).
  SampleND sample(std::span<const float> u) const;
  float pdf(std::span<const float> x) const;  // 0 outside the domain
  void invert(std::span<const float> x, std::span<float> u) const;

  const std::vector<GridAxis>& axes() const { return axes_; }
  uint32_t rows() const { return axes_[0].cells(); }
  uint32_t columns() const { return axes_[1].cells(); }
  std::size_t levels() const { return levels_.size(); }  // stored levels (the 1 × 1 top is not)
  // Stored level k (0 = the grid), for callers that descend it in other arithmetic: the four child
  // masses of each node of the level above, row-major nodes, `parentColumns(k)` nodes per row.
  std::span<const float> blocks(std::size_t k) const { return levels_[k].blocks; }
  uint32_t parentColumns(std::size_t k) const { return levels_[k].parentColumns; }
  bool isUniformFallback() const { return uniformFallback_; }
  std::size_t bytes() const;
  std::vector<double> cellProbabilities() const;  // row-major

 private:
  struct Level {
    uint32_t parentColumns = 0;  // nodes per row of the level above (⌈this level's columns / 2⌉)
    std::vector<float> blocks;   // 4 masses per node of the level above, row-major nodes
  };
  static std::size_t slot(const Level& level, uint32_t row, uint32_t column) {
    return 4 * (std::size_t{row / 2} * level.parentColumns + column / 2) + 2 * (row & 1) + (column & 1);
  }
  double leaf(uint32_t row, uint32_t column) const {
    return levels_.front().blocks[slot(levels_.front(), row, column)];
  }
  float densityOf(double probability) const { return clampDensity(probability / cellArea_); }

  std::vector<GridAxis> axes_;
  std::vector<Level> levels_;  // [0] = the grid, back() = the four children of the top
  double cellArea_ = 0;
  bool uniformFallback_ = false;
};

}  // namespace acdf
