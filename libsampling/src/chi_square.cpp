#include "acdf/sampling/chi_square.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace acdf {

namespace {

// Regularised lower incomplete gamma P(a, x) by its power series (converges fast for x < a + 1).
double lowerGammaSeries(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < 100000; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::fabs(term) < std::fabs(sum) * 1e-16) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Regularised upper incomplete gamma Q(a, x) by its continued fraction (modified Lentz), x >= a + 1.
double upperGammaFraction(double a, double x) {
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < 1e-16) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

double chiSquareSurvival(double x, double dof) {
  if (!(dof > 0.0)) throw std::invalid_argument("chi-square: degrees of freedom must be > 0");
  if (!(x > 0.0)) return 1.0;
  if (std::isinf(x)) return 0.0;
  const double a = 0.5 * dof, half = 0.5 * x;
  return half < a + 1.0 ? 1.0 - lowerGammaSeries(a, half) : upperGammaFraction(a, half);
}

double sidakAlpha(double alpha, uint32_t tests) {
  if (tests == 0) throw std::invalid_argument("sidak: needs at least one test");
  // 1 − (1 − α)^(1/m), written to keep full precision when m is large.
  return -std::expm1(std::log1p(-alpha) / tests);
}

ChiSquareResult chiSquareTest(std::span<const double> observed, std::span<const double> expected, double minExpected) {
  if (observed.size() != expected.size()) throw std::invalid_argument("chi-square: cell counts differ");
  ChiSquareResult result;
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (expected[i] > 0.0) {
      order.push_back(i);
    } else if (observed[i] > 0.0) {
      // Samples where the pdf says none can fall: reject outright.
      result.statistic = std::numeric_limits<double>::infinity();
      result.pvalue = 0.0;
      return result;
    }
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });

  // Pool the smallest cells together until each pool expects at least minExpected.
  std::vector<std::pair<double, double>> pools;  // (observed, expected)
  double pooledObserved = 0.0, pooledExpected = 0.0;
  for (std::size_t i : order) {
    pooledObserved += observed[i];
    pooledExpected += expected[i];
    if (pooledExpected >= minExpected) {
      pools.emplace_back(pooledObserved, pooledExpected);
      pooledObserved = pooledExpected = 0.0;
    }
  }
  if (pooledExpected > 0.0) {
    if (pools.empty())
      pools.emplace_back(pooledObserved, pooledExpected);
    else {
      pools.back().first += pooledObserved;
      pools.back().second += pooledExpected;
    }
  }
  for (const auto& [o, e] : pools) result.statistic += (o - e) * (o - e) / e;
  result.pooledCells = static_cast<uint32_t>(pools.size());
  result.dof = result.pooledCells > 0 ? result.pooledCells - 1 : 0;
  result.pvalue = result.dof > 0 ? chiSquareSurvival(result.statistic, result.dof) : 1.0;
  return result;
}

}  // namespace acdf
