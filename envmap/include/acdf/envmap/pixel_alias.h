#pragma once
// O(1) choice of a pixel by the alias method, in two steps: a row from an alias table of the row
// masses (variate u0), then a column from that row's own alias table (variate u1).
//
// Why not one alias table over all pixels (AliasGrid): a float variate has 24 bits; an alias
// table of n cells spends log2(n) of them on the cell and tests acceptance with the rest. Over
// the 2^19 pixels of a 1024 × 512 map that leaves 5 bits, so every acceptance probability is
// rounded to a multiple of 1/32 and pixels get visibly wrong probabilities (the chi-square test
// rejects it at 1e6 samples); over 4096 × 2048 one bit is left. Rows and columns separately keep
// 24 − log2(height) and 24 − log2(width) bits (14 or more up to 1024 × 1024 cells per axis).
//
// Probabilities are stored as float per table; a pixel's probability is their product in
// double, computed the same way for sample() and probability().

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "acdf/envmap/lat_long.h"
#include "acdf/sampling/alias_table_1d.h"

namespace acdf {

class PixelAlias {
 public:
  // values: height × width, row-major, non-negative, not all zero (throws std::invalid_argument).
  PixelAlias(std::span<const float> values, uint32_t width, uint32_t height);

  struct Pick {
    PixelIndex pixel;
    double probability = 0;   // > 0
    float fractionDown = 0;   // position inside the pixel, uniform in [0, 1)², from the
    float fractionRight = 0;  // variates' unused fractions
  };
  Pick sample(float u0, float u1) const;
  double probability(PixelIndex p) const {
    return double{rows_.probability(p.row)} * double{columns_[p.row].probability(p.column)};
  }

  std::size_t bytes() const;
  std::vector<double> pixelProbabilities() const;  // row-major

  // The tables, for callers that sample them in other arithmetic.
  const AliasTable& rows() const { return rows_; }
  const AliasTable& columns(uint32_t row) const { return columns_[row]; }

 private:
  AliasTable rows_;
  std::vector<AliasTable> columns_;  // one per row; rows without mass are never chosen
};

}  // namespace acdf
