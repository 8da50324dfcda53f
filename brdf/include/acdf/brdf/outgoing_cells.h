#pragma once
// The cells of a tabulated sampler's axes that a direction falls in, without atan2 and hypot:
// OutgoingCells for ωo on the outgoing axes, θo in [0, π/2) and φo in [0, 2π), exactly the
// cells of its angles rounded to float on the axes,
//   θo cell = axis.cellOf(onAxis(axis, polarAngle(ωo))),  φo cell = the same of azimuth(ωo),
// and HalfVectorCells for the half vector ωh on the sampled axes (below). Each cell is a step
// function of a monotone angle, so it is the number of the step's thresholds (found once by
// bisection of that formula) at or below it; the direction is compared with them through
// quantities monotone in the angles that cost no trigonometry, tan(θ/2) = ρ / (|v| + z)
// (ρ = √(x² + y²)) and a pseudo-angle of (x, y). Where one of these lies within rounding reach
// of a threshold, or the direction is degenerate (a pole, below the horizon, not finite, too
// large or small to square), the formula itself decides.

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

// The azimuth a tabulated sampler's half-vector table is laid out in: φh (the 4D layout), or
// Δφ = φh − φo taken in [0, 2π) (isotropic), or folded onto [0, π] by Δφ ↦ 2π − Δφ above π
// (mirrored isotropic).
enum class HalfAzimuth : uint8_t { Absolute, Relative, Folded };

// The cells of a half vector ωh (z > 0) on a tabulated sampler's s axis, s = √(θh / (π/2)) in
// [0, 1), and on its azimuth axis, exactly as the angles give them (cellsFromAngles). Like
// OutgoingCells, by tan(θh/2) and a pseudo-angle compared with thresholds found by bisection of
// that definition. A relative azimuth turns ωh's (x, y) by −φo first, with cos φo and sin φo
// taken as ωo's x and y over its ρ (the factor ρ, which the pseudo-angle does not see, left
// out); that rotation errs by a few ulps of the angle, far inside the margin. Where Δφ comes
// near 0 = 2π the definition's sign of φh − φo is only as good as its rounding, so an unfolded
// relative azimuth keeps the margin from that seam too; a folded one sends both sides to cell 0.
class HalfVectorCells {
 public:
  // The s axis (only its cell count matters) and the azimuth axis, [0, 2π) or [0, π) if folded.
  HalfVectorCells(const GridAxis& sAxis, const GridAxis& phiAxis, HalfAzimuth azimuth);

  // {s cell, azimuth cell} of ωh given ωo (which only a relative azimuth reads).
  std::array<uint32_t, 2> cellsOf(const Vec3d& wo, const Vec3d& wh) const;
  // The definition, and cellsOf's answer near thresholds: s from θh = polarAngle(ωh) in double,
  // the azimuth (azimuth(ωh), minus azimuth(ωo) and folded as the layout says) on its axis.
  std::array<uint32_t, 2> cellsFromAngles(const Vec3d& wo, const Vec3d& wh) const;

 private:
  uint32_t sCells_;
  GridAxis phiAxis_;
  HalfAzimuth azimuth_;
  ThresholdCells halfAngleTangents_;  // tan(θh/2) in [0, 1], stepping up at the s thresholds
  ThresholdCells pseudoAngles_;       // pseudoAngle in [0, 4], stepping up at the azimuth thresholds
};

}  // namespace acdf
