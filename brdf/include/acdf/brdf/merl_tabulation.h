#pragma once
// A model tabulated on MERL's grid as the MERL tools do it (nbrdf_to_merl.py): the model at cell
// (i, j, k)'s corner coordinates θh = (i/90)²·π/2, θd = j/90·π/2, φd = k/180·π, divided by
// MerlBrdf's channel scales; cells where ωi or ωo is at or below the horizon hold −1 (MERL's
// "no data" mark). The neural fits and the analytic presets both become MERL tables this way.

#include <array>
#include <functional>
#include <vector>

#include "acdf/sampling/sphere.h"

namespace acdf {

struct MerlCellCoordinates {
  int thetaHalfIndex, thetaDiffIndex, phiDiffIndex;
  double thetaHalf, thetaDiff, phiDiff;
  Vec3d half;  // (sin θh, 0, cos θh)
  Vec3d diff;  // (sin θd cos φd, sin θd sin φd, cos θd), the difference vector
};

// Whether the tool marks cell (i, j, k) as below the horizon (its wi_z / wo_z test).
bool merlCellBelowHorizon(int thetaHalfIndex, int thetaDiffIndex, int phiDiffIndex);

// 3 · MerlBrdf::kCells values in file order (red block, green block, blue block): linear RGB
// f(cell) / kChannelScale, −1 in the cells below the horizon, where f is not called. Parallel over
// θh (oneTBB), each sine and cosine computed once per row or column, not per cell; the result does
// not depend on the number of threads.
std::vector<double> tabulateMerl(const std::function<std::array<double, 3>(const MerlCellCoordinates&)>& f);

}  // namespace acdf
