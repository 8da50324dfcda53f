#include "acdf/sampling/grid_axis.h"

#include <algorithm>
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

float GridAxis::nudgeInto(float x, uint32_t firstCell, uint32_t endCell) const {
  while (cellOf(x) < firstCell) x = std::nextafter(x, hi_);
  while (cellOf(x) >= endCell) x = std::nextafter(x, lo_);
  return x;
}

}  // namespace acdf
