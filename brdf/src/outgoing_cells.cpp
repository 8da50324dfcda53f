#include "acdf/brdf/outgoing_cells.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace acdf {

namespace {

// How near a threshold a quantity must be for cellsOf to defer to the angles. The quantities and
// the thresholds are each within a few double ulps of exact, and so are atan2 and hypot: 1e-9
// leaves a factor of 10^5 and sends well under 1e-6 of the directions down the slow path.
constexpr double kMargin = 1e-9;

constexpr double kPi = std::numbers::pi;
constexpr double kHalfPi = 0.5 * kPi;
constexpr double kTwoPi = 2.0 * kPi;

// The smallest angle in [0, axis.hi()] whose float coordinate lies in cell k or above, for each
// k in [1, cells): the cell of an angle a is the number of these at or below it, since
// axis.cellOf(onAxis(axis, a)) is non-decreasing in a.
std::vector<double> angleThresholds(const GridAxis& axis) {
  return firstOfEachCell(axis.cells(), axis.hi(), [&](double a) { return axis.cellOf(onAxis(axis, a)); });
}

std::vector<double> pseudoAnglesOf(const GridAxis& phiAxis) {
  std::vector<double> angles;
  for (double phi : angleThresholds(phiAxis)) angles.push_back(pseudoAngle(std::sin(phi), std::cos(phi)));
  return angles;
}

// The s cell of a polar angle θh: s = √(θh / (π/2)) in double, scaled to the cells, clamped.
uint32_t sCellOf(uint32_t cells, double thetaHalf) {
  const double s = std::sqrt(thetaHalf / kHalfPi);
  return static_cast<uint32_t>(std::min<double>(s * cells, cells - 1));
}

}  // namespace

float onAxis(const GridAxis& axis, double x) {
  const float f = static_cast<float>(x);
  if (f >= axis.hi()) return std::nextafter(axis.hi(), axis.lo());
  return f < axis.lo() ? axis.lo() : f;
}

OutgoingCells::OutgoingCells(const GridAxis& thetaAxis, const std::optional<GridAxis>& phiAxis)
    : thetaAxis_(thetaAxis),
      phiAxis_(phiAxis),
      halfAngleTangents_(halfAngleTangents(angleThresholds(thetaAxis)), 1.0, kMargin),
      pseudoAngles_(phiAxis ? pseudoAnglesOf(*phiAxis) : std::vector<double>{}, 4.0, kMargin) {}

std::array<uint32_t, 2> OutgoingCells::cellsFromAngles(const Vec3d& wo) const {
  return {thetaAxis_.cellOf(onAxis(thetaAxis_, polarAngle(wo))),
          phiAxis_ ? phiAxis_->cellOf(onAxis(*phiAxis_, azimuth(wo))) : 0u};
}

std::array<uint32_t, 2> OutgoingCells::cellsOf(const Vec3d& wo) const {
  // Above the horizon |ωo| + z does not cancel.
  if (!(wo.z > 0.0)) return cellsFromAngles(wo);
  const double rho2 = wo.x * wo.x + wo.y * wo.y;
  const std::optional<uint32_t> theta =
      halfAngleTangents_.cellOf(halfAngleTangent(std::sqrt(rho2), std::sqrt(rho2 + wo.z * wo.z), wo.z));
  if (!theta) return cellsFromAngles(wo);
  uint32_t phi = 0;
  if (phiAxis_) {
    // The seam φo = 0 = 2π needs no care: there the pseudo-angle and the azimuth alike wrap from
    // the last cell to cell 0, by the sign of y. The pole (x = y = 0) gives NaN, near no threshold.
    const std::optional<uint32_t> cell = pseudoAngles_.cellOf(pseudoAngle(wo.y, wo.x));
    if (!cell) return cellsFromAngles(wo);
    phi = *cell;
  }
  return {*theta, phi};
}

HalfVectorCells::HalfVectorCells(const GridAxis& sAxis, const GridAxis& phiAxis, HalfAzimuth azimuth)
    : sCells_(sAxis.cells()),
      phiAxis_(phiAxis),
      azimuth_(azimuth),
      halfAngleTangents_(
          halfAngleTangents(firstOfEachCell(sCells_, kHalfPi, [&](double a) { return sCellOf(sCells_, a); })), 1.0,
          kMargin),
      pseudoAngles_(pseudoAnglesOf(phiAxis), 4.0, kMargin) {}

std::array<uint32_t, 2> HalfVectorCells::cellsFromAngles(const Vec3d& wo, const Vec3d& wh) const {
  double phi = azimuth(wh);
  if (azimuth_ != HalfAzimuth::Absolute) {
    phi -= azimuth(wo);
    if (phi < 0.0) phi += kTwoPi;
    if (azimuth_ == HalfAzimuth::Folded && phi > kPi) phi = kTwoPi - phi;
  }
  return {sCellOf(sCells_, polarAngle(wh)), phiAxis_.cellOf(onAxis(phiAxis_, phi))};
}

std::array<uint32_t, 2> HalfVectorCells::cellsOf(const Vec3d& wo, const Vec3d& wh) const {
  // As for ωo in OutgoingCells::cellsOf.
  if (!(wh.z > 0.0)) return cellsFromAngles(wo, wh);
  const double rho2 = wh.x * wh.x + wh.y * wh.y;
  const std::optional<uint32_t> s =
      halfAngleTangents_.cellOf(halfAngleTangent(std::sqrt(rho2), std::sqrt(rho2 + wh.z * wh.z), wh.z));
  if (!s) return cellsFromAngles(wo, wh);
  double x = wh.x, y = wh.y;
  if (azimuth_ != HalfAzimuth::Absolute) {
    // ρo ρh (cos Δφ, sin Δφ), whose length ρo ρh keeps the products clear of underflow and
    // overflow; a pole of either (no azimuth to speak of) is left to the angles.
    const double scale2 = rho2 * (wo.x * wo.x + wo.y * wo.y);
    if (!(scale2 >= 0x1p-900 && scale2 <= 0x1p900)) return cellsFromAngles(wo, wh);
    x = wh.x * wo.x + wh.y * wo.y;
    y = wh.y * wo.x - wh.x * wo.y;
    if (azimuth_ == HalfAzimuth::Folded) y = std::abs(y);
  }
  const double v = pseudoAngle(y, x);
  const bool nearSeam = azimuth_ == HalfAzimuth::Relative && !(v > kMargin && v < 4.0 - kMargin);
  const std::optional<uint32_t> phi = nearSeam ? std::nullopt : pseudoAngles_.cellOf(v);
  if (!phi) return cellsFromAngles(wo, wh);
  return {*s, *phi};
}

}  // namespace acdf
