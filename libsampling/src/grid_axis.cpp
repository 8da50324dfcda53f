#include "acdf/sampling/grid_axis.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace acdf {

GridAxis::GridAxis(uint32_t cells, float lo, float hi) : cells_(cells), lo_(lo), hi_(hi) {
  if (cells == 0) throw std::invalid_argument("grid axis: needs at least one cell");
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi)) {
    throw std::invalid_argument("grid axis: domain [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                ") is not a finite, non-empty interval");
  }
  cellWidth_ = (static_cast<double>(hi) - static_cast<double>(lo)) / cells;
  invCellWidth_ = 1.0 / cellWidth_;
  // Every cell must hold floats strictly inside it, or place() could not return a coordinate in
  // the chosen cell: ask for three ulps of the largest coordinate magnitude.
  const float magnitude = std::max(std::fabs(lo), std::fabs(hi));
  const double ulp = static_cast<double>(std::nextafter(magnitude, std::numeric_limits<float>::infinity())) - magnitude;
  if (cellWidth_ < 3.0 * ulp) {
    throw std::invalid_argument("grid axis: " + std::to_string(cells) + " cells on [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + ") are narrower than float coordinates can resolve");
  }
  const double margin = cellWidth_ * 0x1p-24;
  innerLo_ = std::max(std::nextafter(lo, hi), static_cast<float>(lo + margin));
  innerHi_ = std::min(std::nextafter(hi, lo), static_cast<float>(hi - margin));
  while (cellOf(innerLo_) != 0) innerLo_ = std::nextafter(innerLo_, lo);
  while (cellOf(innerHi_) != cells - 1) innerHi_ = std::nextafter(innerHi_, hi);
}

double GridAxis::gridCoordinate(float x) const {
  return std::clamp(rawGridCoordinate(x), 0.0, static_cast<double>(cells_));
}

namespace {

// Floats as unsigned integers in the order of their values, −0 just below +0.
uint32_t orderedKey(float x) {
  const uint32_t bits = std::bit_cast<uint32_t>(x);
  return bits & 0x80000000u ? ~bits : bits | 0x80000000u;
}
float fromOrderedKey(uint32_t key) { return std::bit_cast<float>(key & 0x80000000u ? key & 0x7FFFFFFFu : ~key); }

}  // namespace

// The float that stepping x one ulp at a time would reach, found by bisection over the floats'
// order: stepping from a cell boundary at or near 0, where floats are densest, would take up to
// about 10^9 steps. cellOf is monotone and gives −0 and +0 the same cell, so the first float at
// or above the boundary in this order is the one stepping reaches (which skips +0 going up and
// −0 going down).
float GridAxis::nudgeInto(float x, uint32_t firstCell, uint32_t endCell) const {
  if (cellOf(x) < firstCell) {
    uint32_t below = orderedKey(x), atOrAbove = orderedKey(hi_);  // cellOf(hi_) = cells − 1
    while (atOrAbove - below > 1) {
      const uint32_t mid = below + (atOrAbove - below) / 2;
      (cellOf(fromOrderedKey(mid)) >= firstCell ? atOrAbove : below) = mid;
    }
    x = fromOrderedKey(atOrAbove);
  }
  if (cellOf(x) >= endCell) {
    uint32_t below = orderedKey(lo_), atOrAbove = orderedKey(x);  // cellOf(lo_) = 0
    while (atOrAbove - below > 1) {
      const uint32_t mid = below + (atOrAbove - below) / 2;
      (cellOf(fromOrderedKey(mid)) >= endCell ? atOrAbove : below) = mid;
    }
    x = fromOrderedKey(below);
  }
  return x;
}

}  // namespace acdf
