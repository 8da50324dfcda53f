#include "acdf/envmap/lat_long.h"

#include <cmath>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

namespace acdf {

namespace {

// pixelOf() trusts comparisons with its cell edges when w's pseudo-angle lies this far inside a
// cell (a pseudo-angle never moves faster than the angle itself): the angles' own rounding
// (atan2, hypot, the scaling to pixels: under 1e-14) cannot carry it across an edge.
constexpr double kEdgeMargin = 1e-9;
// pixelOf()'s squared lengths whose sum neither underflows nor overflows.
constexpr double kMinSquaredLength = 1e-300, kMaxSquaredLength = 1e300;

// The pseudo-angles of the interior cell edges turn · k / cells, 0 < k < cells: where pixelOf()'s
// rows (θ, turn π, pseudo-angles in [0, 2]) or columns (φ, turn 2π, in [0, 4]) step up.
ThresholdCells edgeCells(uint32_t cells, double turn, double range) {
  std::vector<double> edges;
  for (uint32_t k = 1; k < cells; ++k) {
    const double angle = turn * k / cells;
    edges.push_back(pseudoAngle(std::sin(angle), std::cos(angle)));
  }
  return ThresholdCells(std::move(edges), range, kEdgeMargin);
}

}  // namespace

LatLongMapping::LatLongMapping(uint32_t width, uint32_t height)
    : width_(width),
      height_(height),
      cosEdge_(height + 1),
      rowCells_(edgeCells(height, std::numbers::pi, 2)),
      columnCells_(edgeCells(width, 2 * std::numbers::pi, 4)) {
  for (uint32_t r = 0; r <= height; ++r) cosEdge_[r] = std::cos(std::numbers::pi * r / height);
  cosEdge_.front() = 1.0;  // exact at the poles
  cosEdge_.back() = -1.0;
  // atan2 gives θ = π/2 for any y = ±0, and φ = 0, π/2, π, 3π/2 for any x = ±0 with −z >= +0,
  // z = ±0 with x > 0, x = ±0 with −z <= −0, z = ±0 with x < 0.
  equatorRow_ = pixelByAngles({1, 0, 0}).row;
  const Vec3d axes[4] = {{0, 0, -1}, {1, 0, 0}, {0, 0, 1}, {-1, 0, 0}};
  for (int k = 0; k < 4; ++k) axisColumns_[k] = pixelByAngles(axes[k]).column;
}

PixelIndex LatLongMapping::pixelOf(const Vec3d& w) const {
  // A zero y, x or z puts θ or φ exactly on an axis (atan2's exact cases), whose cell the
  // constructor found; elsewhere the pseudo-angles of θ = atan2(hypot(x, z), y) and
  // φ = atan2(x, −z) are compared with the cell edges.
  std::optional<uint32_t> row, column;
  const double horizontal = w.x * w.x + w.z * w.z;
  const double squared = horizontal + w.y * w.y;
  const bool lengthOk = squared >= kMinSquaredLength && squared <= kMaxSquaredLength;  // false for NaN
  if (w.y == 0)
    row = equatorRow_;
  else if (lengthOk)
    row = rowCells_.cellOf(pseudoAngle(std::sqrt(horizontal), w.y));
  const double a = w.x, b = -w.z;
  if (a == 0)
    column = axisColumns_[std::signbit(b) ? 2 : 0];
  else if (b == 0)
    column = axisColumns_[a > 0 ? 1 : 3];
  else if (lengthOk)  // |a| + |b| cannot overflow
    column = columnCells_.cellOf(pseudoAngle(a, b));
  if (row && column) return {*row, *column};
  return pixelByAngles(w);
}

}  // namespace acdf
