#pragma once
// How much a compressed distribution costs in variance, measured exactly from cell probabilities.

#include <span>

namespace acdf {

struct CompressionQuality {
  // Σ p²/q − Σ p over the reachable cells (p > 0 and q > 0): the relative variance that
  // importance sampling p with q instead adds (0 when q = p). With all mass reachable and both
  // summing to 1 this is the usual Σ p²/q − 1; unreachable mass is reported apart, not mixed in.
  double chi2Divergence = 0;
  double maxWeightRatio = 0;   // max p/q over cells with p > 0 and q > 0
  double unreachableMass = 0;  // Σ p over cells with q == 0 (sampling q can never reach them)
};

// p: reference cell probabilities (the function's), q: the approximating distribution's. Both
// should sum to 1; sums are accumulated in double.
CompressionQuality compareCellProbabilities(std::span<const double> p, std::span<const double> q);

}  // namespace acdf
