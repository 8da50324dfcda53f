#pragma once
// Pearson's chi-square goodness-of-fit test, used by the test suite and by `acdf cdf-stats` /
// `acdf chi2` so users can check a sampler on their own data.

#include <cstdint>
#include <span>

namespace acdf {

struct ChiSquareResult {
  double statistic = 0;
  uint32_t dof = 0;   // pooled cells − 1
  double pvalue = 1;  // P(χ²_dof ≥ statistic); 0 if samples fell where nothing was expected
  uint32_t pooledCells = 0;
};

// observed: sample counts per cell; expected: N × (probability of the cell under the pdf). Cells
// are sorted by expected count and the smallest pooled until every pool expects >= minExpected.
ChiSquareResult chiSquareTest(std::span<const double> observed, std::span<const double> expected,
                              double minExpected = 5.0);

// Upper tail Q(dof/2, x/2) of the chi-square distribution (regularised incomplete gamma).
double chiSquareSurvival(double x, double dof);

// Per-test significance level keeping the family-wise level `alpha` over `tests` tests (Šidák).
double sidakAlpha(double alpha, uint32_t tests);

}  // namespace acdf
