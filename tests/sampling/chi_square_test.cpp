// The chi-square statistics (acdf::chiSquareSurvival, sidakAlpha, chiSquareTest) against known
// values, and proof that the test harness can fail: samplers with a wrong pdf, a wrong sample
// distribution, samples outside the domain or an inconsistent returned pdf are all rejected.

#include "acdf/sampling/chi_square.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "acdf/sampling/cascade.h"
#include "acdf/sampling/piecewise_constant_1d.h"
#include "acdf/test_support/chi_square_harness.h"
#include "acdf/test_support/samplers.h"

namespace {

using namespace acdf;
using namespace acdf::test_support;

// Reference values computed with mpmath (gammainc(k/2, x/2, inf, regularized=True)), 30 digits.
struct Known {
  double x, dof, q;
};
constexpr Known kKnown[] = {
    {3.841459, 1, 0.0499999946531958},     {23.209, 10, 0.0100008658147408},
    {10, 2, 0.00673794699908547},  // exp(-5)
    {135.807, 100, 0.0099995737292488},    {1106.969, 1000, 0.00999999685390744},
    {10233.75, 10000, 0.0499992083855754}, {101000, 100000, 0.0128688403772337},
    {0.5, 3, 0.918891411654676},           {1e-3, 1, 0.97477287936996},
    {50, 1, 1.53745979442803e-12},         {200, 10, 1.61393053369773e-37},
};

TEST(ChiSquareSurvival, KnownValues) {
  for (const Known& k : kKnown) {
    const double q = chiSquareSurvival(k.x, k.dof);
    EXPECT_NEAR(q, k.q, 1e-7 * k.q) << "x=" << k.x << " dof=" << k.dof;
  }
}

TEST(ChiSquareSurvival, EdgesAndClosedForms) {
  EXPECT_DOUBLE_EQ(chiSquareSurvival(0.0, 5), 1.0);
  for (double x : {0.1, 1.0, 4.0, 17.0, 60.0}) {
    // dof = 2: Q = exp(-x/2); dof = 4: Q = exp(-x/2)(1 + x/2).
    EXPECT_NEAR(chiSquareSurvival(x, 2), std::exp(-x / 2), 1e-10 * std::exp(-x / 2)) << x;
    EXPECT_NEAR(chiSquareSurvival(x, 4), std::exp(-x / 2) * (1 + x / 2), 1e-10 * std::exp(-x / 2) * (1 + x / 2)) << x;
  }
  // Monotone decreasing in x.
  double previous = 1.0;
  for (double x = 0.5; x < 3000; x *= 1.3) {
    const double q = chiSquareSurvival(x, 500);
    EXPECT_LE(q, previous) << x;
    EXPECT_GE(q, 0.0);
    previous = q;
  }
}

TEST(SidakAlpha, MatchesClosedForm) {
  EXPECT_NEAR(sidakAlpha(0.01, 1), 0.01, 1e-15);
  EXPECT_NEAR(sidakAlpha(0.01, 100), 0.000100498308241667901, 1e-15);  // mpmath
  EXPECT_NEAR(sidakAlpha(0.05, 20), 1.0 - std::pow(0.95, 1.0 / 20), 1e-15);
  // The family-wise level is kept: 1 − (1 − a)^m = α.
  for (uint32_t m : {2u, 10u, 1000u, 100000u}) {
    const double a = sidakAlpha(0.01, m);
    EXPECT_NEAR(1.0 - std::pow(1.0 - a, m), 0.01, 1e-10) << m;
    EXPECT_LT(a, 0.01 / m * 1.01) << m;  // close to Bonferroni for small α
    EXPECT_GT(a, 0.01 / m) << m;
  }
}

TEST(ChiSquareTest, PerfectFitAndDof) {
  const std::vector<double> e = {100, 200, 300, 400};
  const ChiSquareResult r = chiSquareTest(e, e);
  EXPECT_EQ(r.statistic, 0.0);
  EXPECT_EQ(r.dof, 3u);
  EXPECT_EQ(r.pooledCells, 4u);
  EXPECT_DOUBLE_EQ(r.pvalue, 1.0);
}

TEST(ChiSquareTest, StatisticAndPvalue) {
  const std::vector<double> expected = {100, 100, 100};
  const std::vector<double> observed = {110, 90, 100};
  const ChiSquareResult r = chiSquareTest(observed, expected);
  EXPECT_NEAR(r.statistic, 2.0, 1e-12);
  EXPECT_EQ(r.dof, 2u);
  EXPECT_NEAR(r.pvalue, std::exp(-1.0), 1e-10);
}

TEST(ChiSquareTest, PoolsSmallCells) {
  // Five cells expecting 1 each pool into one cell expecting 5; the two large cells stay.
  const std::vector<double> expected = {1, 100, 1, 1, 100, 1, 1};
  const std::vector<double> observed = {4, 95, 0, 3, 95, 0, 3};
  const ChiSquareResult r = chiSquareTest(observed, expected);
  EXPECT_EQ(r.pooledCells, 3u);
  EXPECT_EQ(r.dof, 2u);
  // Pool: observed 10 vs expected 5 → 5; the large cells: 2 × 25/100.
  EXPECT_NEAR(r.statistic, 5.5, 1e-12);
  EXPECT_NEAR(r.pvalue, std::exp(-2.75), 1e-10);
  // Without pooling (minExpected 0) the statistic sees every cell.
  const ChiSquareResult raw = chiSquareTest(observed, expected, 0.0);
  EXPECT_EQ(raw.pooledCells, 7u);
  EXPECT_NEAR(raw.statistic, 9 + 0.25 + 1 + 4 + 0.25 + 1 + 4, 1e-12);
}

TEST(ChiSquareTest, SamplesWhereNothingExpectedGivePvalueZero) {
  const std::vector<double> expected = {0, 500, 500};
  const std::vector<double> observed = {1, 500, 499};
  EXPECT_EQ(chiSquareTest(observed, expected).pvalue, 0.0);
  // No samples where nothing is expected: the zero cell is harmless.
  const std::vector<double> fine = {0, 500, 500};
  EXPECT_DOUBLE_EQ(chiSquareTest(fine, expected).pvalue, 1.0);
}

TEST(ChiSquareTest, DetectsAShiftOfOnePercentWithManySamples) {
  std::vector<double> expected(100, 1e4), observed(100, 1e4);
  for (int i = 0; i < 50; ++i) observed[i] += 300, observed[50 + i] -= 300;  // 3σ per cell
  EXPECT_LT(chiSquareTest(observed, expected).pvalue, 1e-6);
}

// ---- The harness can fail -----------------------------------------------------------------

// A 16×16 uniform Cascade: every cell has mass 1/256, so moving 10% between cells keeps ∫pdf = 1.
struct UniformGrid {
  std::vector<float> values = std::vector<float>(256, 1.0f);
  std::vector<GridAxis> axes = {GridAxis(16), GridAxis(16)};
  Cascade cascade{values, axes, uniformOptions()};
  static CascadeOptions uniformOptions() {
    CascadeOptions o;
    o.methods = {DimensionMethod::Uniform, DimensionMethod::Uniform};
    return o;
  }
  // Factor applied to the reported density of cell (i, j): cells 17 and 200 ×1.1, 40 and 99 ×0.9.
  static double factor(std::size_t cell) {
    if (cell == 17 || cell == 200) return 1.1;
    if (cell == 40 || cell == 99) return 0.9;
    return 1.0;
  }
};

ACDF_CHI_SQUARE_TEST(Harness, AcceptsTheCorrectSampler, 1) {
  const UniformGrid g;
  const ChiSquareReport r = runChiSquare(
      g.axes, [&](std::span<const float> u) { return g.cascade.sample(u); },
      [&](std::span<const float> x) { return g.cascade.pdf(x); }, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r));
}

ACDF_CHI_SQUARE_TEST(Harness, RejectsAPdfPerturbedByTenPercentInFourCells, 1) {
  const UniformGrid g;
  auto perturbed = [&](std::span<const float> x) {
    return static_cast<float>(g.cascade.pdf(x) * UniformGrid::factor(cellIndex(g.axes, x)));
  };
  // Sampling unchanged; the reported pdf (both sample().pdf and pdf()) perturbed consistently, so
  // only the chi-square test can notice.
  const ChiSquareReport r = runChiSquare(
      g.axes,
      [&](std::span<const float> u) {
        SampleND s = g.cascade.sample(u);
        s.pdf = perturbed(std::span<const float>(s.x.data(), 2));
        return s;
      },
      perturbed, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(r.samplesValid()) << r.summary();
  EXPECT_TRUE(r.integralValid()) << r.summary();
  EXPECT_FALSE(r.chiSquarePassed()) << r.summary();
  EXPECT_FALSE(r.passed());
}

ACDF_CHI_SQUARE_TEST(Harness, RejectsASamplerThatDrawsFromTheWrongDistribution, 1) {
  // Samples come from a 1D table where 3 of 64 cells are 10% heavier; the pdf is the true one.
  std::vector<float> truth(64, 1.0f), wrong(64, 1.0f);
  wrong[5] = wrong[30] = wrong[31] = 1.1f;
  const PiecewiseConstant1D t(truth), w(wrong);
  const std::vector<GridAxis> axes = {t.axis()};
  const ChiSquareReport r = runChiSquare(
      axes,
      [&](float u) {
        Sample1D s = w.sample(u);
        s.pdf = t.pdf(s.x);
        return s;
      },
      [&](float x) { return t.pdf(x); }, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(r.samplesValid()) << r.summary();
  EXPECT_FALSE(r.chiSquarePassed()) << r.summary();
}

ACDF_CHI_SQUARE_TEST(Harness, RejectsInvalidSamples, 2) {
  const PiecewiseConstant1D t(std::vector<float>(64, 1.0f));
  const std::vector<GridAxis> axes = {t.axis()};
  ChiSquareOptions o;
  o.samples = 1'000'000;

  // Returned pdf off by 1e-4 relative: the per-sample check catches it.
  const ChiSquareReport mismatch = runChiSquare(
      axes,
      [&](float u) {
        Sample1D s = t.sample(u);
        s.pdf *= 1.0001f;
        return s;
      },
      [&](float x) { return t.pdf(x); }, o);
  EXPECT_EQ(mismatch.pdfMismatch, o.samples) << mismatch.summary();
  EXPECT_FALSE(mismatch.passed());

  // Samples on the domain's boundary (x = lo) are outside the open domain.
  ChiSquareReport boundary;
  SampleND s;
  s.x[0] = 0.0f;
  s.pdf = 1.0f;
  const float u[] = {0.0f};
  EXPECT_FALSE(checkSample(
      axes, u, s, [&](std::span<const float> x) { return t.pdf(x[0]); }, 1e-5, boundary));
  EXPECT_EQ(boundary.outsideDomain, 1u);
  // A zero or NaN returned pdf is bad.
  s.x[0] = 0.5f;
  s.pdf = 0.0f;
  checkSample(
      axes, u, s, [&](std::span<const float> x) { return t.pdf(x[0]); }, 1e-5, boundary);
  s.pdf = std::nanf("");
  checkSample(
      axes, u, s, [&](std::span<const float> x) { return t.pdf(x[0]); }, 1e-5, boundary);
  EXPECT_EQ(boundary.badPdf, 2u);
  EXPECT_FALSE(boundary.samplesValid());

  // A pdf integrating to 1.001 fails the integral check even with a consistent sampler.
  const ChiSquareReport scaled = runChiSquare(
      axes,
      [&](float v) {
        Sample1D q = t.sample(v);
        q.pdf *= 1.001f;
        return q;
      },
      [&](float x) { return t.pdf(x) * 1.001f; }, o);
  EXPECT_TRUE(scaled.samplesValid()) << scaled.summary();
  EXPECT_FALSE(scaled.integralValid()) << scaled.summary();
}

ACDF_CHI_SQUARE_TEST(Harness, BinsCanBeUnionsOrSubdivisionsOfCells, 2) {
  // A uniform table sampled correctly passes with coarse and fine bins; a sampler that only uses
  // the left half of every cell passes with cell bins (it cannot see inside cells) but fails
  // with bins that subdivide cells.
  const PiecewiseConstant1D t(std::vector<float>(50, 1.0f));
  const std::vector<GridAxis> axes = {t.axis()};
  ChiSquareOptions coarse, fine;
  coarse.bins = {10};
  fine.bins = {200};
  auto good = [&](float u) { return t.sample(u); };
  auto pdf = [&](float x) { return t.pdf(x); };
  EXPECT_TRUE(Passed(runChiSquare(axes, good, pdf, coarse)));
  auto leftHalf = [&](float u) {
    Sample1D s = t.sample(u);
    const uint32_t cell = t.axis().cellOf(s.x);
    const double frac = t.axis().gridCoordinate(s.x) - cell;
    s.x = t.axis().place(cell, cell + 1, frac * 0.5);
    return s;
  };
  const ChiSquareReport r = runChiSquare(axes, leftHalf, pdf, fine);
  EXPECT_FALSE(r.chiSquarePassed()) << r.summary();
}

}  // namespace
