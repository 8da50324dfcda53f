#include "acdf/sampling/threshold_cells.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace acdf {

ThresholdCells::ThresholdCells(std::vector<double> thresholds, double range, double margin)
    : range_(range), margin_(margin) {
  if (!(std::isfinite(range) && range > 0.0))
    throw std::invalid_argument("threshold cells: range " + std::to_string(range) + " is not finite and positive");
  // A bin's start and v · binsPerUnit_ round apart by under range · 2^-52, which can put v in the
  // bin next to its own; then a threshold within that distance of v spoils the bracket, and this
  // margin already defers v.
  if (!(std::isfinite(margin) && margin >= range * 0x1p-50))
    throw std::invalid_argument("threshold cells: margin " + std::to_string(margin) +
                                " is not finite and at least range · 2^-50");
  if (thresholds.size() >= std::numeric_limits<uint32_t>::max())
    throw std::invalid_argument("threshold cells: more than 2^32-2 thresholds");
  // The closest two thresholds (or the range, for fewer than two), while checking them.
  double closest = range, previous = 0.0;
  for (std::size_t k = 0; k < thresholds.size(); ++k) {
    const double t = thresholds[k];
    if (!(t > previous && t < range))
      throw std::invalid_argument("threshold cells: threshold " + std::to_string(k) + " (" + std::to_string(t) +
                                  ") is not above the one before and inside (0, " + std::to_string(range) + ")");
    if (k > 0) closest = std::min(closest, t - previous);
    previous = t;
  }
  const auto bins = static_cast<std::size_t>(std::ceil(2.0 * range / closest));
  binsPerUnit_ = bins / range;
  below_.resize(bins + 1);
  for (std::size_t b = 0; b <= bins; ++b)
    below_[b] = static_cast<uint32_t>(std::lower_bound(thresholds.begin(), thresholds.end(), b / binsPerUnit_) -
                                      thresholds.begin());
  edges_.reserve(thresholds.size() + 2);
  edges_.push_back(-std::numeric_limits<double>::infinity());
  edges_.insert(edges_.end(), thresholds.begin(), thresholds.end());
  edges_.push_back(std::numeric_limits<double>::infinity());
}

}  // namespace acdf
