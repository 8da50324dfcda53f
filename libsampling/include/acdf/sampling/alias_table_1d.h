#pragma once
// Vose's alias method: O(1) sampling of a discrete distribution over n cells (AliasTable), and
// the continuous piecewise-constant distribution over [lo, hi) it induces, uniform within the
// chosen cell (AliasTable1D).
//
// Precision: built in double; stores per cell the acceptance probability (float), the alias
// (uint32) and the cell's probability (float, returned as the pdf): 12 bytes a cell.
// One variate (sample(u)) is split into a cell slot (log2 n bits) and an acceptance fraction
// (the rest): a float variate on the 2^-24 lattice a generator returns leaves 24 − log2(n) bits for
// the acceptance test, so every acceptance probability is in effect rounded to a multiple of
// 2^-(24 − log2 n). Measured exactly over all 2^24 variates (acdf_stress), the worst cell's
// probability is off by 0.06% at 2^12 cells, 1.2% at 2^16, 11% at 2^19 and 33% at 2^21 (a
// chi-square test of 1e6 samples rejects it from 2^21 cells, of 1e7 from 2^19); at 2^23 a cell
// gets 0 or twice its probability. The one-variate form, and AliasTable1D, which has one variate,
// are therefore exact only for small tables (up to ~2^16 cells). sample(uCell, uAccept) takes the
// acceptance from a second variate (full 24 bits) and is exact up to 2^24 cells; AliasGrid uses
// it whenever it has two or more axes. The position inside the cell reuses the variates' unused
// fractions.
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

  // One variate: the cell slot and the acceptance test share u (see the precision note above).
  // remapped is u's fraction after both.
  Discrete sample(float u) const;
  // Two variates: uCell picks the slot (every slot is reachable up to 2^24 cells), uAccept runs the
  // acceptance test. remapped is uAccept's fraction after the test; uCell's fraction within its
  // slot (24 − log2 n bits) is cellFraction().
  Discrete sample(float uCell, float uAccept) const;
  float cellFraction(float uCell) const;
  float probability(uint32_t index) const { return cells_[index].probability; }
  // Slot `slot`'s acceptance probability and alias, for callers that sample it in other arithmetic.
  float acceptance(uint32_t slot) const { return cells_[slot].accept; }
  uint32_t alias(uint32_t slot) const { return cells_[slot].alias; }

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
  // The slot of u in [0,1) and u's fraction inside it.
  std::size_t slotOf(float u, double& fraction) const;
  Discrete accept(std::size_t slot, double fraction) const;
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
