#include "acdf/sampling/quality.h"

#include <algorithm>
#include <stdexcept>

namespace acdf {

CompressionQuality compareCellProbabilities(std::span<const double> p, std::span<const double> q) {
  if (p.size() != q.size()) throw std::invalid_argument("quality: cell counts differ");
  CompressionQuality result;
  double sum = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p[i] <= 0.0) continue;
    if (q[i] <= 0.0) {
      result.unreachableMass += p[i];
      continue;
    }
    sum += p[i] * p[i] / q[i];
    result.maxWeightRatio = std::max(result.maxWeightRatio, p[i] / q[i]);
  }
  // Σ p²/q − Σ p, not − 1: the reachable mass need not be exactly 1 after rounding.
  double reachable = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p[i] > 0.0 && q[i] > 0.0) reachable += p[i];
  }
  result.chi2Divergence = std::max(0.0, sum - reachable);
  return result;
}

}  // namespace acdf
