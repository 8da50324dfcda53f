#pragma once
// The alias-method baseline on an N-D grid: one alias table over all cells (row-major), O(1)
// cell choice, uniform position inside the cell. No conditioning dimensions.
//
// With two or more axes, u[0] picks the alias table's slot and u[1] runs its acceptance test
// (AliasTable::sample(uCell, uAccept)), so cell probabilities are exact up to 2^24 cells; the
// position along axis 0 reuses u[0]'s fraction within its slot (24 − log2(cells) bits of
// resolution), along axis 1 u[1]'s fraction after the test, along axis d > 1 u[d]. A
// one-axis grid has one variate for all three (AliasTable1D's precision limit applies).
// Throws std::invalid_argument for more than 2^24 cells: a float variate cannot reach every slot.

#include <cstddef>
#include <span>
#include <vector>

#include "acdf/sampling/alias_table_1d.h"
#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/sample.h"

namespace acdf {

class AliasGrid {
 public:
  AliasGrid(std::span<const float> values, std::vector<GridAxis> axes);

  SampleND sample(std::span<const float> u) const;
  float pdf(std::span<const float> x) const;

  std::size_t dims() const { return axes_.size(); }
  const std::vector<GridAxis>& axes() const { return axes_; }
  bool isUniformFallback() const { return table_.isUniformFallback(); }
  std::size_t bytes() const { return table_.bytes(); }
  std::vector<double> cellProbabilities() const;

 private:
  std::vector<GridAxis> axes_;
  std::vector<std::size_t> strides_;
  double cellVolume_;
  AliasTable table_;
};

}  // namespace acdf
