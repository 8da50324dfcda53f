#pragma once
// One axis of a regular grid: `cells` equal cells over the half-open domain [lo, hi).
//
// Every distribution in libsampling is piecewise constant on such a grid, so the axis owns the
// two mappings all of them need: a coordinate to its cell, and a position inside a range of cells
// back to a coordinate. Both are written so that they agree exactly in float arithmetic: a
// coordinate produced by place() for cells [first, end) always maps back into [first, end), and
// always lies strictly inside (lo, hi) (never on the boundary, where e.g. sinθ = 0 at a pole).

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace acdf {

class GridAxis {
 public:
  // Throws std::invalid_argument unless cells >= 1, lo < hi are finite and each cell is wide
  // enough (at least 3 float ulps) to hold coordinates strictly inside it.
  explicit GridAxis(uint32_t cells, float lo = 0.0f, float hi = 1.0f);

  uint32_t cells() const { return cells_; }
  float lo() const { return lo_; }
  float hi() const { return hi_; }
  double cellWidth() const { return cellWidth_; }

  bool contains(float x) const { return x >= lo_ && x < hi_; }

  // The cell holding x, clamped to [0, cells-1]. Monotone non-decreasing in x.
  uint32_t cellOf(float x) const {
    const double g = rawGridCoordinate(x);
    if (!(g > 0.0)) return 0;
    if (g >= cells_) return cells_ - 1;
    return static_cast<uint32_t>(g);
  }

  // Continuous grid coordinate of x in [0, cells] (cell k spans [k, k+1)).
  double gridCoordinate(float x) const;

  // The coordinate at fraction t in [0,1] of the cell range [firstCell, endCell), nudged so that
  // cellOf(result) is in [firstCell, endCell) and innerLo() <= result <= innerHi().
  float place(uint32_t firstCell, uint32_t endCell, double t) const { return placeOnGrid(firstCell, endCell, t).x; }

  // place()'s coordinate with its cellOf() and gridCoordinate(), which place() has at hand when
  // it checks the cell: a caller that needs the cell and the fraction in it need not find them
  // again from x.
  struct Placed {
    float x;
    uint32_t cell;
    double gridCoordinate;
  };
  Placed placeOnGrid(uint32_t firstCell, uint32_t endCell, double t) const {
    const double g = firstCell + std::clamp(t, 0.0, 1.0) * (endCell - firstCell);
    const float x = std::clamp(static_cast<float>(lo_ + g * cellWidth_), innerLo_, innerHi_);
    // cellOf(x) is in [firstCell, endCell) whenever x's unclamped grid coordinate is (the cell
    // bounds are integers), so one comparison settles the common case; the rare nudge stays out
    // of line, so no value of a caller's loop has to survive its calls.
    const double placed = rawGridCoordinate(x);
    if (placed >= firstCell && placed < endCell) [[likely]]  // inside [0, cells): cellOf's floor, no clamp
      return {x, static_cast<uint32_t>(placed), placed};
    const float nudged = nudgeInto(x, firstCell, endCell);
    return {nudged, cellOf(nudged), gridCoordinate(nudged)};
  }

  // Density (w.r.t. this axis' length measure) of probability `mass` spread evenly over
  // `cellCount` cells. Used identically by sample() and pdf() so the two agree bit for bit.
  double density(double mass, uint32_t cellCount) const { return mass / (static_cast<double>(cellCount) * cellWidth_); }

  // The extreme coordinates place() returns: a 2^-24 fraction of a cell inside the domain (so a
  // sample at u = 0 is not a denormal when lo = 0, and sinθ-style Jacobians stay finite).
  float innerLo() const { return innerLo_; }
  float innerHi() const { return innerHi_; }

  bool operator==(const GridAxis&) const = default;

 private:
  // Grid coordinate of x, unclamped.
  double rawGridCoordinate(float x) const { return (static_cast<double>(x) - lo_) * invCellWidth_; }

  // x moved by whole ulps until cellOf(x) is in [firstCell, endCell): rounding may have carried
  // it across a cell boundary. The constructor guarantees each cell holds interior floats, so
  // the answer is a few ulps away; near 0 that can be a great many floats, hence a bisection.
  float nudgeInto(float x, uint32_t firstCell, uint32_t endCell) const;

  uint32_t cells_;
  float lo_, hi_;
  double cellWidth_;
  double invCellWidth_;
  float innerLo_, innerHi_;
};

}  // namespace acdf
