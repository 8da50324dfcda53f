#include "acdf/envmap/portal_table.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <tbb/parallel_for.h>

#include "acdf/envmap/environment_light.h"

namespace acdf {

namespace {
// Fine cells per side: at the square's middle a cell spans 2 / cells radians, two thirds of a
// pixel of the map's rows (π / height), and at least 1/64 rad for small maps; at most 4096 (64 MB
// of function, maps of more than 4K rows).
uint32_t fineCells(const EnvironmentMap& map) { return std::clamp<uint32_t>(map.height(), 128, 4096); }
// Each fine cell's value is the mean of 3 × 3 points in it: cells and pixels do not share edges,
// and a cell's value from its middle alone is a pixel's it only partly covers. One point per cell
// at twice this resolution leaves 1.24× the variance per sample of nine at this one (a sun-lit
// room through its window, scenes/room-portal.json); nine points here match four per cell at
// twice the resolution for half the map lookups.
constexpr int kPointsPerSide = 3;
}  // namespace

PortalTable::PortalTable(const Portal& portal, const EnvironmentMap& map, const Rotation& worldFromMap,
                         const SimplifyOptions& options)
    : corner_(portal.corner),
      axisU_(normalize(portal.edgeU)),
      axisV_(normalize(portal.edgeV)),
      normal_(normalize(cross(portal.edgeU, portal.edgeV))),
      lengthU_(length(portal.edgeU)),
      lengthV_(length(portal.edgeV)),
      // The frame above is set (members in declaration order) before the table reads it.
      table_(build(*this, map, worldFromMap, options)),
      minPower_(kMinShare * table_.mass({0, 1, 0, 1})) {}

WindowedTable2D PortalTable::build(const PortalTable& frame, const EnvironmentMap& map, const Rotation& worldFromMap,
                                   const SimplifyOptions& options) {
  const uint32_t cells = fineCells(map);
  std::vector<float> function(static_cast<std::size_t>(cells) * cells);
  tbb::parallel_for(uint32_t{0}, cells, [&](uint32_t j) {
    for (uint32_t i = 0; i < cells; ++i) {
      double sum = 0;
      for (int pj = 0; pj < kPointsPerSide; ++pj)
        for (int pi = 0; pi < kPointsPerSide; ++pi) {
          const double a = (i + (pi + 0.5) / kPointsPerSide) / cells, b = (j + (pj + 0.5) / kPointsPerSide) / cells;
          const Vec3d w = frame.directionAt(a, b);
          sum += map.radiance(worldFromMap.applyInverse(w)).luminance() * frame.coordinatesOf(w)->jacobian;
        }
      function[static_cast<std::size_t>(j) * cells + i] = static_cast<float>(sum / (kPointsPerSide * kPointsPerSide));
    }
  });
  return WindowedTable2D(function, cells, cells, options);
}

std::optional<PortalTable::Coordinates> PortalTable::coordinatesOf(const Vec3d& w) const {
  const double du = dot(w, axisU_), dv = dot(w, axisV_), dn = -dot(w, normal_);
  if (!(dn > 0)) return std::nullopt;
  const double qu = std::sqrt(du * du + dn * dn), qv = std::sqrt(dv * dv + dn * dn);
  return Coordinates{0.5 * (1.0 + du / qu), 0.5 * (1.0 + dv / qv), 4.0 * (qu * qu * qu) * (qv * qv * qv) / (dn * dn * dn)};
}

Vec3d PortalTable::directionAt(double a, double b) const {
  // s / √(1 − s²) with 1 ± s from a and 1 − a, exact near either end.
  const double x = (2.0 * a - 1.0) / (2.0 * std::sqrt(a * (1.0 - a)));
  const double y = (2.0 * b - 1.0) / (2.0 * std::sqrt(b * (1.0 - b)));
  return normalize(axisU_ * x + axisV_ * y - normal_);
}

std::optional<WindowedTable2D::Window> PortalTable::windowFrom(const Vec3d& position) const {
  const Vec3d toCorner = corner_ - position;
  const double h = -dot(toCorner, normal_);
  if (!(h > 0)) return std::nullopt;
  const double u0 = dot(toCorner, axisU_), v0 = dot(toCorner, axisV_);
  auto coordinate = [h](double d) { return 0.5 * (1.0 + d / std::sqrt(d * d + h * h)); };
  return WindowedTable2D::Window{coordinate(u0), coordinate(u0 + lengthU_), coordinate(v0), coordinate(v0 + lengthV_)};
}

PortalTable::View PortalTable::viewFrom(const Vec3d& position) const {
  const std::optional<WindowedTable2D::Window> window = windowFrom(position);
  if (!window) return {};
  const double power = table_.mass(*window);
  return {*window, power > minPower_ ? power : 0.0};
}

Vec3d PortalTable::sample(const View& view, double u0, double u1) const {
  const WindowedTable2D::Sample s = table_.sample(view.window, view.power, u0, u1);
  return directionAt(s.a, s.b);
}

double PortalTable::densityThrough(const WindowedTable2D::Window& window, const Vec3d& w) const {
  const std::optional<Coordinates> c = coordinatesOf(w);
  // Written to fail for NaN coordinates too.
  if (!c || !(c->a >= window.a0 && c->a <= window.a1 && c->b >= window.b0 && c->b <= window.b1)) return 0.0;
  return table_.density(c->a, c->b) / c->jacobian;
}

}  // namespace acdf
