#include "acdf/brdf/merl_tabulation.h"

#include <cmath>
#include <cstddef>
#include <numbers>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "acdf/brdf/merl.h"

namespace acdf {

namespace {

// The tool's cell coordinates, written in its order of operations.
double cellThetaHalf(int i) {
  const double s = i / 90.0;
  return s * s * (std::numbers::pi / 2);
}
double cellThetaDiff(int j) { return j / 90.0 * (std::numbers::pi / 2); }
double cellPhiDiff(int k) { return k / 180.0 * std::numbers::pi; }

// wi = R_y(θh) d, wo = reflect(wi, h), h = (sin θh, 0, cos θh): below if either z ≤ 0.
bool belowHorizon(const Vec3d& half, const Vec3d& diff) {
  const double c = half.z, s = half.x;
  const double wiZ = -s * diff.x + c * diff.z;
  const double wiX = c * diff.x + s * diff.z;
  const double hDotWi = s * wiX + c * wiZ;
  const double woZ = 2 * hDotWi * c - wiZ;
  return wiZ <= 0 || woZ <= 0;
}

Vec3d halfVector(double thetaHalf) { return {std::sin(thetaHalf), 0.0, std::cos(thetaHalf)}; }
Vec3d diffVector(double sinThetaDiff, double cosThetaDiff, double phiDiff) {
  return {sinThetaDiff * std::cos(phiDiff), sinThetaDiff * std::sin(phiDiff), cosThetaDiff};
}

}  // namespace

bool merlCellBelowHorizon(int i, int j, int k) {
  const double td = cellThetaDiff(j);
  return belowHorizon(halfVector(cellThetaHalf(i)), diffVector(std::sin(td), std::cos(td), cellPhiDiff(k)));
}

std::vector<double> tabulateMerl(const std::function<std::array<double, 3>(const MerlCellCoordinates&)>& f) {
  constexpr std::size_t kCells = MerlBrdf::kCells;
  std::array<double, MerlBrdf::kPhiDiffCells> cosPhi, sinPhi;
  for (int k = 0; k < MerlBrdf::kPhiDiffCells; ++k) {
    cosPhi[k] = std::cos(cellPhiDiff(k));
    sinPhi[k] = std::sin(cellPhiDiff(k));
  }
  std::vector<double> table(3 * kCells);
  tbb::parallel_for(tbb::blocked_range<int>(0, MerlBrdf::kThetaHalfCells), [&](const tbb::blocked_range<int>& r) {
    MerlCellCoordinates cell{};
    for (int i = r.begin(); i != r.end(); ++i) {
      cell.thetaHalfIndex = i;
      cell.thetaHalf = cellThetaHalf(i);
      cell.half = halfVector(cell.thetaHalf);
      for (int j = 0; j < MerlBrdf::kThetaDiffCells; ++j) {
        cell.thetaDiffIndex = j;
        cell.thetaDiff = cellThetaDiff(j);
        const double sinTd = std::sin(cell.thetaDiff), cosTd = std::cos(cell.thetaDiff);
        for (int k = 0; k < MerlBrdf::kPhiDiffCells; ++k) {
          cell.phiDiffIndex = k;
          cell.phiDiff = cellPhiDiff(k);
          cell.diff = {sinTd * cosPhi[k], sinTd * sinPhi[k], cosTd};
          const std::size_t index = MerlBrdf::flatIndex(i, j, k);
          if (belowHorizon(cell.half, cell.diff)) {
            for (int c = 0; c < 3; ++c) table[c * kCells + index] = -1.0;
            continue;
          }
          const std::array<double, 3> value = f(cell);
          for (int c = 0; c < 3; ++c) table[c * kCells + index] = value[c] / MerlBrdf::kChannelScale[c];
        }
      }
    }
  });
  return table;
}

}  // namespace acdf
