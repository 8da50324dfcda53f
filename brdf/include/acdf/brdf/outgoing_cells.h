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
#include <cstdint>
#include <optional>
#include <vector>

#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/sphere.h"
#include "acdf/sampling/threshold_cells.h"

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
  GridAxis thetaAxis_;
  std::optional<GridAxis> phiAxis_;
  ThresholdCells halfAngleTangents_;  // tan(θ/2) in [0, 1], stepping up at the θo thresholds
  ThresholdCells pseudoAngles_;       // pseudoAngle in [0, 4], stepping up at the φo thresholds
};

}  // namespace acdf
