#pragma once
// Option sets that differ from a base in exactly one field each, for tests that something (a
// cache key, a description) follows every field.

#include <cmath>
#include <vector>

#include "acdf/sampling/simplify.h"

namespace acdf::test_support {

inline std::vector<SimplifyOptions> simplifyVariants(const SimplifyOptions& base) {
  std::vector<SimplifyOptions> v(5, base);
  v[0].method = base.method == Simplifier::DouglasPeucker ? Simplifier::GreedyRefinement : Simplifier::DouglasPeucker;
  v[1].metric = base.metric == ErrorMetric::ChiSquare ? ErrorMetric::Vertical : ErrorMetric::ChiSquare;
  v[2].epsilon = std::nextafter(base.epsilon, 1.0);
  v[3].maxPoints = base.maxPoints + 7;
  v[4].weightBound = base.weightBound == 2.0 ? 3.0 : 2.0;
  return v;
}

}  // namespace acdf::test_support
