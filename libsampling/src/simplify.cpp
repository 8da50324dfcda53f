#include "acdf/sampling/simplify.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <stdexcept>
#include <string>

#include "acdf/sampling/enum_names.h"

namespace acdf {

namespace {

// Where a segment [a, b] is split (its interior vertex farthest from the chord), and its error.
struct Worst {
  uint32_t vertex = 0;
  double error = 0.0;  // 0 for segments without interior vertices
};

// Every metric splits at the vertex farthest (vertically) from the chord: there the mass of the
// two halves is most out of proportion to their widths. For ChiSquare this is a proxy for the
// split that minimises the halves' contributions, and a more robust one: χ² is not reduced by a
// single split of interleaved structure (alternating blocks of mass h and 0 contribute h per
// empty cell wherever they are cut), so that greedy choice peels off cells one at a time there
// (1542 points instead of 9 on a 4096-cell checkerboard); the two gave the same compression and
// variance on the measured BRDFs (see docs/engine.md).
class Chords {
 public:
  Chords(std::span<const float> cdf, ErrorMetric metric) : cdf_(cdf), metric_(metric) {}

  Worst worst(uint32_t a, uint32_t b) const {
    Worst w{a, 0.0};
    if (b - a < 2) return w;
    const double fa = cdf_[a];
    const double slope = (static_cast<double>(cdf_[b]) - fa) / (b - a);
    for (uint32_t k = a + 1; k < b; ++k) {
      const double deviation = std::fabs(cdf_[k] - (fa + slope * (k - a)));
      if (deviation > w.error) w = {k, deviation};
    }
    if (w.error == 0.0) w.vertex = a + (b - a) / 2;
    switch (metric_) {
      case ErrorMetric::Vertical: break;
      case ErrorMetric::Perpendicular: {
        // In the unit square (x = k/n): distance = vertical deviation × cos(chord angle).
        const double n = static_cast<double>(cdf_.size() - 1);
        const double dx = (b - a) / n, dy = slope * (b - a);
        w.error *= dx / std::hypot(dx, dy);
        break;
      }
      case ErrorMetric::ChiSquare: w.error = chiSquare(a, b); break;
    }
    return w;
  }

 private:
  // The χ² contribution of [a, b) (see simplify.h). A direct sum rather than prefix sums of p²
  // over the CDF: the chord scan above is O(b − a) anyway, and a sum local to the interval does
  // not cancel against the squared masses of the rest of the CDF.
  double chiSquare(uint32_t a, uint32_t b) const {
    const double mass = static_cast<double>(cdf_[b]) - cdf_[a];
    if (mass <= 0.0) return 0.0;
    double sumSquares = 0.0;
    for (uint32_t k = a; k < b; ++k) {
      const double p = static_cast<double>(cdf_[k + 1]) - cdf_[k];
      sumSquares += p * p;
    }
    // >= 0 by Cauchy–Schwarz; the clamp only removes rounding.
    return std::max(0.0, (b - a) * sumSquares / mass - mass);
  }

  std::span<const float> cdf_;
  ErrorMetric metric_;
};

struct Segment {
  uint32_t a, b;
  Worst worst;
  bool operator<(const Segment& o) const { return worst.error < o.worst.error; }
};

std::vector<uint32_t> douglasPeucker(const Chords& chords, uint32_t n, double epsilon) {
  std::vector<uint32_t> kept{0, n};
  // Explicit stack: recursion depth can reach n on adversarial curves.
  std::vector<std::pair<uint32_t, uint32_t>> stack{{0, n}};
  while (!stack.empty()) {
    auto [a, b] = stack.back();
    stack.pop_back();
    const Worst w = chords.worst(a, b);
    if (b - a < 2 || w.error <= epsilon) continue;
    kept.push_back(w.vertex);
    stack.push_back({a, w.vertex});
    stack.push_back({w.vertex, b});
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}

std::vector<uint32_t> greedyRefinement(const Chords& chords, uint32_t n, double epsilon, uint32_t maxPoints) {
  std::vector<uint32_t> kept{0, n};
  std::priority_queue<Segment> queue;
  queue.push({0, n, chords.worst(0, n)});
  while (!queue.empty() && (maxPoints == 0 || kept.size() < maxPoints)) {
    const Segment s = queue.top();
    queue.pop();
    if (s.b - s.a < 2 || s.worst.error <= epsilon) break;  // the worst left is good enough
    const uint32_t v = s.worst.vertex;
    kept.push_back(v);
    queue.push({s.a, v, chords.worst(s.a, v)});
    queue.push({v, s.b, chords.worst(v, s.b)});
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}

// True if some cell of [a, b) carries more than rho times the interval's average cell mass.
bool exceedsWeightBound(std::span<const float> cdf, uint32_t a, uint32_t b, double rho) {
  const double limit = rho * (static_cast<double>(cdf[b]) - cdf[a]) / (b - a);
  for (uint32_t k = a; k < b; ++k) {
    if (static_cast<double>(cdf[k + 1]) - cdf[k] > limit) return true;
  }
  return false;
}

std::vector<uint32_t> enforceWeightBound(const Chords& chords, std::span<const float> cdf, std::vector<uint32_t> kept,
                                         double rho) {
  std::vector<uint32_t> added;
  std::vector<std::pair<uint32_t, uint32_t>> stack;
  for (std::size_t i = 0; i + 1 < kept.size(); ++i) stack.push_back({kept[i], kept[i + 1]});
  while (!stack.empty()) {
    auto [a, b] = stack.back();
    stack.pop_back();
    if (b - a < 2 || !exceedsWeightBound(cdf, a, b, rho)) continue;
    // Cells of unequal mass make the CDF bend, so the worst vertex is a proper interior split.
    const uint32_t v = chords.worst(a, b).vertex;
    added.push_back(v);
    stack.push_back({a, v});
    stack.push_back({v, b});
  }
  kept.insert(kept.end(), added.begin(), added.end());
  std::sort(kept.begin(), kept.end());
  return kept;
}

}  // namespace

void validate(const SimplifyOptions& o) {
  const auto fail = [](const char* option, const std::string& problem) {
    throw OptionError("simplify", option, problem);
  };
  if (!(o.epsilon >= 0.0) || !std::isfinite(o.epsilon))
    fail("epsilon", "must be finite and >= 0, got " + OptionError::number(o.epsilon));
  if (!(o.weightBound == 0.0 || o.weightBound >= 1.0))
    fail("weight_bound", "must be 0 (no bound) or >= 1, got " + OptionError::number(o.weightBound));
  if (o.metric != ErrorMetric::Vertical && o.metric != ErrorMetric::Perpendicular && o.metric != ErrorMetric::ChiSquare)
    fail("metric", "is unknown (" + std::to_string(static_cast<int>(o.metric)) + ")");
  if (o.maxPoints != 0 && o.maxPoints < 2) fail("max_points", "must be at least 2 (the end points)");
  if (o.maxPoints != 0 && o.method == Simplifier::DouglasPeucker)
    fail("max_points", "needs the greedy simplifier, not douglas-peucker");
}

std::vector<uint32_t> simplifyCdf(std::span<const float> cdf, const SimplifyOptions& options) {
  validate(options);
  if (cdf.size() < 2) throw std::invalid_argument("simplify: a CDF needs at least 2 values");
  const auto n = static_cast<uint32_t>(cdf.size() - 1);
  const Chords chords(cdf, options.metric);
  std::vector<uint32_t> kept = options.method == Simplifier::DouglasPeucker
                                   ? douglasPeucker(chords, n, options.epsilon)
                                   : greedyRefinement(chords, n, options.epsilon, options.maxPoints);
  if (options.weightBound >= 1.0) kept = enforceWeightBound(chords, cdf, std::move(kept), options.weightBound);
  return kept;
}

uint32_t worstVertex(std::span<const float> cdf, uint32_t a, uint32_t b, ErrorMetric metric) {
  if (b < a + 2 || b >= cdf.size()) throw std::invalid_argument("simplify: no interior vertex to split at");
  return Chords(cdf, metric).worst(a, b).vertex;
}

namespace {
constexpr EnumName<Simplifier> kSimplifierNames[] = {{Simplifier::DouglasPeucker, "douglas-peucker"},
                                                     {Simplifier::GreedyRefinement, "greedy"}};
constexpr EnumName<ErrorMetric> kErrorMetricNames[] = {
    {ErrorMetric::Vertical, "vertical"}, {ErrorMetric::Perpendicular, "perpendicular"}, {ErrorMetric::ChiSquare, "chi-square"}};
}  // namespace

std::string_view toString(Simplifier s) { return nameOf(kSimplifierNames, s); }
std::string_view toString(ErrorMetric m) { return nameOf(kErrorMetricNames, m); }

Simplifier parseSimplifier(std::string_view name) { return valueNamed(kSimplifierNames, name, "simplifier"); }
ErrorMetric parseErrorMetric(std::string_view name) { return valueNamed(kErrorMetricNames, name, "error metric"); }

}  // namespace acdf
