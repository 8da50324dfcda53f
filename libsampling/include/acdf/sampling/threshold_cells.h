#pragma once
// The cell a monotone quantity falls in, given the values at which the cell steps up: how the
// pseudo-angle (pseudoAngle in sphere.h) and tan(θ/2) replace atan2 and hypot in cell lookups. A
// caller whose cells are a function of an angle (a lat-long pixel, a grid axis of the angle) maps
// the angle of each cell boundary to the quantity once; the cell of a direction is then the
// number of these thresholds at or below its quantity, found with one table step.
//
// Exactness. The caller's quantity and thresholds are each within rounding of exact, and so is
// its definition of the cell (atan2, hypot, the scaling to cells). cellOf() answers only when the
// quantity lies more than a margin (above those errors) from every threshold: then no threshold
// lies between it and the exact value, nor between the definition's angle and the exact angle
// (the quantity never moves faster than the angle), so all three count the same thresholds.
// Otherwise it answers nothing and the caller falls back to its definition. The ends 0 and range
// need no margin: the count does not step there, and a definition clamps (atan2 + 2π may round
// up to 2π) so that it too gives the first cell at one end and the last at the other.

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace acdf {

class ThresholdCells {
 public:
  // The cells of a quantity in [0, range] that steps up at each of `thresholds`: strictly
  // increasing, inside (0, range); range finite and > 0; margin finite and >= range · 2^-50
  // (below that, rounding in the bins could defer a v the margin clears). Throws
  // std::invalid_argument otherwise. The margin is fixed here, with the thresholds it keeps
  // away from: it is one rounding bound of the caller's, the same for every lookup.
  ThresholdCells(std::vector<double> thresholds, double range, double margin);

  // The number of thresholds <= v when v lies in [0, range] and more than the margin from every
  // threshold; nothing otherwise (NaN included). The thresholds bracketing the answer are
  // compared, so the bins only make it fast, never wrong.
  std::optional<uint32_t> cellOf(double v) const {
    if (!(v >= 0.0 && v <= range_)) return std::nullopt;
    uint32_t cell = below_[static_cast<std::ptrdiff_t>(v * binsPerUnit_)];
    if (v >= edges_[cell + 1]) ++cell;
    if (v - edges_[cell] > margin_ && edges_[cell + 1] - v > margin_) return cell;
    return std::nullopt;
  }

 private:
  // −∞, the thresholds, +∞: cell k lies between edges k and k + 1, and the first and the last
  // cells keep no margin from the ends.
  std::vector<double> edges_;
  // For equal bins of [0, range] no wider than half the closest two thresholds, so that each
  // holds at most one, the number of thresholds below each bin's start; one more bin for
  // v = range.
  std::vector<uint32_t> below_;
  double binsPerUnit_ = 0, range_, margin_;
};

// For a cell function of x >= 0 that is non-decreasing on [0, hi] and gives `cells` − 1 or more
// at hi: for each k in [1, cells), the smallest double x in [0, hi] in cell k or above, found by
// bisection over the doubles' bit patterns (ordered like the values for x >= 0). The thresholds
// of a cell function defined by rounded arithmetic, exactly as that arithmetic has them.
template <class CellOf>
std::vector<double> firstOfEachCell(uint32_t cells, double hi, CellOf cellOf) {
  std::vector<double> firsts;
  for (uint32_t k = 1; k < cells; ++k) {
    uint64_t below = 0, atOrAbove = std::bit_cast<uint64_t>(hi);
    while (atOrAbove - below > 1) {
      const uint64_t mid = below + (atOrAbove - below) / 2;
      (static_cast<int64_t>(cellOf(std::bit_cast<double>(mid))) >= k ? atOrAbove : below) = mid;
    }
    firsts.push_back(std::bit_cast<double>(atOrAbove));
  }
  return firsts;
}

// tan(θ/2) = ρ / (|v| + z) of a vector v = (x, y, z) at polar angle θ = atan2(ρ, z), given
// ρ = √(x² + y²) and |v|, for z > −|v|: monotone in θ, without atan2. NaN, which has no cell,
// where |v| lies outside [2^-450, 2^450]: there the squares could overflow or lose the angle to
// underflow (a ρ² that underflows leaves tan(θ/2) far below every threshold).
inline double halfAngleTangent(double rho, double length, double z) {
  return length >= 0x1p-450 && length <= 0x1p450 ? rho / (length + z) : std::numeric_limits<double>::quiet_NaN();
}

// tan(θ/2) of each polar angle θ: thresholds for halfAngleTangent.
inline std::vector<double> halfAngleTangents(std::vector<double> angles) {
  for (double& a : angles) a = std::tan(0.5 * a);
  return angles;
}

}  // namespace acdf
