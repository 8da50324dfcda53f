#pragma once
// The alias-method baseline on an N-D grid: one alias table over all cells (row-major), O(1)
// cell choice, uniform position inside the cell. No conditioning dimensions.
//
// u[0] chooses the cell; the position along axis 0 reuses u[0]'s unused fraction (see
// AliasTable1D), the position along axis d > 0 uses u[d].

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
