#pragma once
// Validation shared by every constructor that takes tabulated values.

#include <cstddef>
#include <span>
#include <vector>

#include "acdf/sampling/grid_axis.h"

namespace acdf {

// Throws std::invalid_argument naming the first negative, NaN or Inf value ("value at index i
// (cell [a, b]) is NaN"), with the cell shown when a multi-dimensional shape is given.
void checkNonNegativeFinite(std::span<const float> values, std::span<const GridAxis> axes = {});

// Throws std::invalid_argument unless 1 <= axes.size() <= kMaxDims and values.size() equals the
// product of the cell counts (checked for overflow).
void checkGridShape(std::size_t valueCount, std::span<const GridAxis> axes);

}  // namespace acdf
