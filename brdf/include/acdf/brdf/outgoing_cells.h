#pragma once
// The cells of a tabulated sampler's outgoing axes, θo in [0, π/2) and φo in [0, 2π), that a
// direction ωo falls in: exactly the cells of its angles rounded to float on the axes,
//   θo cell = axis.cellOf(onAxis(axis, polarAngle(ωo))),  φo cell = the same of azimuth(ωo),
// without atan2 and hypot. Each cell is a step function of a monotone angle, so it is the
// number of the step's thresholds (found once by bisection of that formula) at or below it;
// ωo is compared with them through quantities monotone in the angles that cost no trigonometry,
// tan(θo/2) = ρ / (|ωo| + z) (ρ = √(x² + y²)) and a pseudo-angle of (x, y). Where one of these
// lies within rounding reach of a threshold, or ωo is degenerate (a pole, below the horizon, not
// finite, too large or small to square), the formula itself decides.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/sphere.h"

namespace acdf {

// x as a coordinate of the axis: rounded to float and kept inside [lo, hi), since a double just
// below hi (2π, say) may round up to it.
float onAxis(const GridAxis& axis, double x);

class OutgoingCells {
 public:
  // The θo axis, and the φo axis if the table has one.
  OutgoingCells(const GridAxis& thetaAxis, const std::optional<GridAxis>& phiAxis);

  // {θo cell, φo cell (0 without a φo axis)}.
  std::array<uint32_t, 2> cellsOf(const Vec3d& wo) const;
  // The same from the angles themselves: the definition, and cellsOf's answer near thresholds.
  std::array<uint32_t, 2> cellsFromAngles(const Vec3d& wo) const;
  // The row-major index of ωo's cells, θo cell · φo cells + φo cell: the slice of a Cascade
  // whose conditioning axes are these (Cascade::sliceOf of ωo's angles on the axes).
  std::size_t sliceOf(const Vec3d& wo) const {
    const std::array<uint32_t, 2> cells = cellsOf(wo);
    return phiAxis_ ? std::size_t{cells[0]} * phiAxis_->cells() + cells[1] : cells[0];
  }

 private:
  // Sorted values in [0, range] of a monotone quantity at which the cell steps up by one, and
  // for equal bins of [0, range], each holding at most one of them, the number below each bin.
  class Thresholds {
   public:
    Thresholds(std::vector<double> at, double range);
    // The number of thresholds <= v, unless v is within `margin` of one that brackets it (or NaN).
    // The bracket is checked, so the bins only make the answer fast, never wrong.
    std::optional<uint32_t> cellOf(double v, double margin) const {
      const double bin = v * binsPerUnit_;
      if (!(bin >= 0.0 && bin < static_cast<double>(below_.size()))) return std::nullopt;
      uint32_t cell = below_[static_cast<std::size_t>(bin)];
      if (cell < at_.size() && v >= at_[cell]) ++cell;
      const bool clearBelow = cell == 0 || v - at_[cell - 1] > margin;
      const bool clearAbove = cell == at_.size() || at_[cell] - v > margin;
      if (clearBelow && clearAbove) return cell;
      return std::nullopt;
    }

   private:
    std::vector<double> at_;
    std::vector<uint32_t> below_;
    double binsPerUnit_;
  };

  GridAxis thetaAxis_;
  std::optional<GridAxis> phiAxis_;
  Thresholds halfAngleTangents_;  // tan(θ/2) at the θo thresholds
  Thresholds pseudoAngles_;       // pseudoAngle at the φo thresholds
};

}  // namespace acdf
