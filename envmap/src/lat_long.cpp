#include "acdf/envmap/lat_long.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>

namespace acdf {

namespace {

// pixelOf() trusts comparisons with its cell edges when w's pseudo-angle lies this far inside a
// cell (a pseudo-angle never moves faster than the angle itself): the angles' own rounding
// (atan2, hypot, the scaling to pixels: under 1e-14) cannot carry it across an edge.
constexpr double kEdgeMargin = 1e-9;
// pixelOf()'s squared lengths whose sum neither underflows nor overflows.
constexpr double kMinSquaredLength = 1e-300, kMaxSquaredLength = 1e300;


}  // namespace

LatLongMapping::LatLongMapping(uint32_t width, uint32_t height)
    : width_(width), height_(height), cosEdge_(height + 1), rowCells_(height, false), columnCells_(width, true) {
  for (uint32_t r = 0; r <= height; ++r) cosEdge_[r] = std::cos(std::numbers::pi * r / height);
  cosEdge_.front() = 1.0;  // exact at the poles
  cosEdge_.back() = -1.0;
  // atan2 gives θ = π/2 for any y = ±0, and φ = 0, π/2, π, 3π/2 for any x = ±0 with −z >= +0,
  // z = ±0 with x > 0, x = ±0 with −z <= −0, z = ±0 with x < 0.
  equatorRow_ = pixelByAngles({1, 0, 0}).row;
  const Vec3d axes[4] = {{0, 0, -1}, {1, 0, 0}, {0, 0, 1}, {-1, 0, 0}};
  for (int k = 0; k < 4; ++k) axisColumns_[k] = pixelByAngles(axes[k]).column;
}

LatLongMapping::AngleCells::AngleCells(uint32_t cells, bool wholeTurn) : edges(cells + 1) {
  const double turn = wholeTurn ? 2 * std::numbers::pi : std::numbers::pi, range = wholeTurn ? 4 : 2;
  edges.front() = wholeTurn ? 0 : -1;
  edges.back() = wholeTurn ? range : range + 1;
  for (uint32_t k = 1; k < cells; ++k) {
    const double angle = turn * k / cells;
    edges[k] = pseudoAngle(std::sin(angle), std::cos(angle));
  }
  const uint32_t buckets = 2 * cells;
  bucketsPerUnit = buckets / range;
  bucketCell.resize(buckets);
  for (uint32_t j = 0; j < buckets; ++j) {
    const auto above = std::upper_bound(edges.begin() + 1, edges.end() - 1, j / bucketsPerUnit);
    bucketCell[j] = static_cast<uint32_t>(above - edges.begin() - 1);
  }
}

std::optional<uint32_t> LatLongMapping::AngleCells::wellInside(double v) const {
  // Past the end (the seam at φ = 2π), or NaN: the steps below would leave the edges. (A
  // pseudo-angle is >= 0.)
  if (!(v >= edges.front() && v < edges.back())) return std::nullopt;
  uint32_t i = bucketCell[std::min(static_cast<std::size_t>(v * bucketsPerUnit), bucketCell.size() - 1)];
  // Steps down only when rounding put v's bucket past it.
  while (v >= edges[i + 1]) ++i;
  while (v < edges[i]) --i;
  if (v - edges[i] > kEdgeMargin && edges[i + 1] - v > kEdgeMargin) return i;
  return std::nullopt;
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
    row = rowCells_.wellInside(pseudoAngle(std::sqrt(horizontal), w.y));
  const double a = w.x, b = -w.z;
  if (a == 0)
    column = axisColumns_[std::signbit(b) ? 2 : 0];
  else if (b == 0)
    column = axisColumns_[a > 0 ? 1 : 3];
  else if (lengthOk)  // |a| + |b| cannot overflow
    column = columnCells_.wellInside(pseudoAngle(a, b));
  if (row && column) return {*row, *column};
  return pixelByAngles(w);
}

}  // namespace acdf
