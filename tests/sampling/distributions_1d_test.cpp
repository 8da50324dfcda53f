// PiecewiseConstant1D, AliasTable1D and AdaptiveCdf1D: chi-square on every fixture, zero cells
// never sampled, invert, cell probabilities, and the adaptive CDF's use of simplifyCdf. The domain
// contract (samples inside, pdf(sample) = returned pdf, ∫pdf = 1, pdf 0 outside) is checked for
// every class in domain_contract_test.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include "acdf/sampling/adaptive_cdf_1d.h"
#include "acdf/sampling/alias_table_1d.h"
#include "acdf/sampling/piecewise_constant_1d.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/simplify.h"
#include "acdf/test_support/chi_square_harness.h"
#include "acdf/test_support/samplers.h"

namespace {

using namespace acdf;
using namespace acdf::test_support;

constexpr uint32_t kCells = 1000;

std::vector<float> fixture1D(Fixture f, uint32_t n = kCells) {
  const uint32_t dims[] = {n};
  return makeFixture(f, dims);
}

constexpr Kind1D kKinds[] = {Kind1D::PiecewiseConstant, Kind1D::Alias, Kind1D::Adaptive};

using Param = std::tuple<Kind1D, Fixture>;

class Distribution1D : public ::testing::TestWithParam<Param> {
 protected:
  Kind1D kind() const { return std::get<0>(GetParam()); }
  Fixture fixture() const { return std::get<1>(GetParam()); }
  std::vector<float> values() const { return fixture1D(fixture()); }
  Sampler sampler() const {
    const auto v = values();
    return make1D(kind(), v);
  }
};

std::string paramName(const ::testing::TestParamInfo<Param>& info) {
  return toString(std::get<0>(info.param)) + "_" + toString(std::get<1>(info.param));
}

ACDF_CHI_SQUARE_TEST_P(Distribution1D, ChiSquare, 1) {
  const Sampler s = sampler();
  const ChiSquareReport r = runChiSquare(s, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r));
}

TEST_P(Distribution1D, NeverSamplesZeroCells) {
  // Samples land only in cells of positive value (for the adaptive CDF only where the weight
  // bound and ε keep zero runs apart: checked through pdf() > 0 instead).
  const Sampler s = sampler();
  const auto v = values();
  Pcg32 rng(3);
  for (int i = 0; i < 200'000; ++i) {
    const float u = rng.nextFloat();
    const SampleND x = s.sample(std::span<const float>(&u, 1));
    const uint32_t cell = s.axes[0].cellOf(x.x[0]);
    ASSERT_GT(s.pdf(std::span<const float>(x.x.data(), 1)), 0.0f) << "u=" << u;
    if (kind() != Kind1D::Adaptive) {
      ASSERT_GT(v[cell], 0.0f) << "u=" << u << " cell " << cell;
    }
  }
}

// PiecewiseConstant1D and AdaptiveCdf1D have invert().
class Invertible1D : public Distribution1D {};

TEST_P(Invertible1D, InvertRecoversTheVariate) {
  const Sampler s = sampler();
  ASSERT_TRUE(s.invert);
  Pcg32 rng(11);
  std::vector<float> us = {0.0f, kOneMinusEpsilon, 0.5f, 1e-7f, 0.999999f};
  for (int i = 0; i < 100'000; ++i) us.push_back(rng.nextFloat());
  int compared = 0;
  for (float u : us) {
    const SampleND x = s.sample(std::span<const float>(&u, 1));
    if (!(x.pdf > 0)) continue;  // zero-mass points have no unique inverse
    float back = -1;
    s.invert(std::span<const float>(x.x.data(), 1), std::span<float>(&back, 1));
    ASSERT_NEAR(back, u, 1e-4) << "x=" << x.x[0];
    ++compared;
  }
  EXPECT_EQ(compared, int(us.size()));
}

// The uncompressed tables (the adaptive CDF is checked interval by interval below).
class Exact1D : public Distribution1D {};

TEST_P(Exact1D, CellProbabilitiesMatchTheFunction) {
  // pdf × cell width against value / Σ values. The piecewise-constant table stores a float CDF
  // (absolute error ~1 ulp of 1 per cell); the alias table stores each probability as a float.
  const Sampler s = sampler();
  const auto exact = exactCellProbabilities(values());
  const auto fromPdf = pdfCellProbabilities(s.axes, s.pdf);
  ASSERT_EQ(exact.size(), fromPdf.size());
  for (std::size_t i = 0; i < exact.size(); ++i) {
    const double tolerance = kind() == Kind1D::Alias ? 1e-6 * exact[i] : 2.5e-7 + 1e-5 * exact[i];
    ASSERT_NEAR(fromPdf[i], exact[i], tolerance) << "cell " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(AllFixtures, Distribution1D,
                         ::testing::Combine(::testing::ValuesIn(kKinds), ::testing::ValuesIn(kAllFixtures)), paramName);
INSTANTIATE_TEST_SUITE_P(AllFixtures, Invertible1D,
                         ::testing::Combine(::testing::Values(Kind1D::PiecewiseConstant, Kind1D::Adaptive),
                                            ::testing::ValuesIn(kAllFixtures)),
                         paramName);
INSTANTIATE_TEST_SUITE_P(AllFixtures, Exact1D,
                         ::testing::Combine(::testing::Values(Kind1D::PiecewiseConstant, Kind1D::Alias),
                                            ::testing::ValuesIn(kAllFixtures)),
                         paramName);

// ---- Other domains ------------------------------------------------------------------------------

class OtherDomain1D : public ::testing::TestWithParam<Kind1D> {};

ACDF_CHI_SQUARE_TEST_P(OtherDomain1D, ChiSquareOnMinus3To5, 1) {
  const auto v = fixture1D(Fixture::Random, 800);
  const Sampler s = make1D(GetParam(), v, -3.0f, 5.0f);
  EXPECT_EQ(s.axes[0].lo(), -3.0f);
  EXPECT_EQ(s.axes[0].hi(), 5.0f);
  const ChiSquareReport r = runChiSquare(s, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r));
  // The density is w.r.t. length on [-3, 5): a uniform function has pdf 1/8.
  const std::vector<float> flat(16, 2.0f);
  const Sampler u = make1D(GetParam(), flat, -3.0f, 5.0f);
  for (float x : {-2.99f, -1.0f, 0.0f, 4.99f}) EXPECT_NEAR(u.pdf(std::span<const float>(&x, 1)), 0.125f, 1e-7f);
}

ACDF_CHI_SQUARE_TEST_P(OtherDomain1D, PositionsAreUniformWithinCells, 1) {
  // Bins subdividing every cell in 4: the position inside the chosen cell (the alias table
  // reuses the variate's unused fraction) must be uniform too.
  const auto v = fixture1D(Fixture::Random, 250);
  const Sampler s = make1D(GetParam(), v, -3.0f, 5.0f);
  ChiSquareOptions o;
  o.bins = {1000};
  const ChiSquareReport r = runChiSquare(s, o);
  recordReport(r);
  EXPECT_TRUE(Passed(r));
}

INSTANTIATE_TEST_SUITE_P(AllKinds, OtherDomain1D, ::testing::ValuesIn(kKinds),
                         [](const auto& info) { return toString(info.param); });

// ---- AdaptiveCdf1D specifics ------------------------------------------------------------------

struct AdaptiveVariant {
  std::string name;
  SimplifyOptions options;
};

std::vector<AdaptiveVariant> adaptiveVariants() {
  std::vector<AdaptiveVariant> v;
  SimplifyOptions o;
  o.method = Simplifier::GreedyRefinement;
  v.push_back({"GreedyVertical", o});
  o = {};
  o.metric = ErrorMetric::Perpendicular;
  v.push_back({"DouglasPeuckerPerpendicular", o});
  o = {};
  o.method = Simplifier::GreedyRefinement;
  o.metric = ErrorMetric::Perpendicular;
  o.maxPoints = 20;
  v.push_back({"GreedyPerpendicularBudget20", o});
  o = {};
  o.epsilon = 0.05;
  o.weightBound = 0;
  v.push_back({"CoarseNoWeightBound", o});
  return v;
}

class AdaptiveOptions1D : public ::testing::TestWithParam<std::tuple<int, Fixture>> {};

ACDF_CHI_SQUARE_TEST_P(AdaptiveOptions1D, ChiSquare, 1) {
  const AdaptiveVariant variant = adaptiveVariants()[std::get<0>(GetParam())];
  const auto v = fixture1D(std::get<1>(GetParam()));
  const Sampler s = make1D(Kind1D::Adaptive, v, 0.0f, 1.0f, variant.options);
  const ChiSquareReport r = runChiSquare(s, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r)) << variant.name;
}

INSTANTIATE_TEST_SUITE_P(Variants, AdaptiveOptions1D,
                         ::testing::Combine(::testing::Range(0, 4),
                                            ::testing::Values(Fixture::Smooth, Fixture::ZerosWithIslands)),
                         [](const auto& info) {
                           return adaptiveVariants()[std::get<0>(info.param)].name + "_" +
                                  toString(std::get<1>(info.param));
                         });

std::vector<SimplifyOptions> allOptionCombinations() {
  std::vector<SimplifyOptions> out;
  for (Simplifier m : {Simplifier::DouglasPeucker, Simplifier::GreedyRefinement})
    for (ErrorMetric metric : {ErrorMetric::Vertical, ErrorMetric::Perpendicular})
      for (double rho : {0.0, 4.0}) {
        SimplifyOptions o;
        o.method = m;
        o.metric = metric;
        o.weightBound = rho;
        out.push_back(o);
      }
  return out;
}

TEST(AdaptiveCdf1D, KeepsTheVerticesSimplifyCdfChooses) {
  for (Fixture f : kAllFixtures) {
    const auto v = fixture1D(f);
    const PiecewiseConstant1D table(v);
    for (const SimplifyOptions& o : allOptionCombinations()) {
      const AdaptiveCdf1D a(v, 0.0f, 1.0f, o);
      const auto expected = simplifyCdf(table.cdf(), o);
      ASSERT_EQ(a.points(), expected.size()) << toString(f);
      for (std::size_t j = 0; j < a.points(); ++j) {
        ASSERT_EQ(a.vertex(j), expected[j]) << toString(f) << " point " << j;
        // Every stored CDF value is the uniform table's value at that vertex.
        ASSERT_EQ(a.cdfAt(j), table.cdf()[expected[j]]) << toString(f) << " point " << j;
      }
    }
  }
}

TEST(AdaptiveCdf1D, PdfIsTheIntervalMassSpreadEvenly) {
  const auto v = fixture1D(Fixture::Random);
  const AdaptiveCdf1D a(v);
  const auto exact = exactCellProbabilities(v);
  for (std::size_t j = 0; j + 1 < a.points(); ++j) {
    const uint32_t first = a.vertex(j), end = a.vertex(j + 1);
    const double mass = std::accumulate(exact.begin() + first, exact.begin() + end, 0.0);
    const float x = a.axis().place(first, end, 0.5);
    EXPECT_NEAR(a.pdf(x) * a.axis().cellWidth() * (end - first), mass, 2.5e-7 + 1e-5 * mass) << "interval " << j;
  }
}

TEST(AdaptiveCdf1D, CompressesSmoothFunctions) {
  const auto v = fixture1D(Fixture::Smooth);
  const AdaptiveCdf1D a(v);
  const PiecewiseConstant1D p(v);
  EXPECT_LT(a.points(), p.cdf().size() / 5);
  EXPECT_LT(a.bytes(), p.bytes() / 3);
  std::cout << "smooth 1000 cells: adaptive " << a.points() << " points, " << a.bytes() << " bytes; uniform "
            << p.bytes() << " bytes\n";
}

TEST(AdaptiveCdf1D, GreedyBudgetIsHonoured) {
  const auto v = fixture1D(Fixture::Random);
  SimplifyOptions o;
  o.method = Simplifier::GreedyRefinement;
  o.epsilon = 0;
  o.weightBound = 0;
  o.maxPoints = 37;
  EXPECT_EQ(AdaptiveCdf1D(v, 0.0f, 1.0f, o).points(), 37u);
}

TEST(AdaptiveCdf1D, VertexIndicesUseTheNarrowestWidth) {
  // A single bump keeps ~5 points whatever the size; 8-bit indices up to 255 cells, 16-bit up to
  // 65535, 32-bit beyond.
  for (uint32_t n : {255u, 256u, 65535u, 65536u}) {
    std::vector<float> v(n, 0.0f);
    v[n / 3] = 1.0f;
    const AdaptiveCdf1D a(v);
    const std::size_t indexBytes = n <= 255 ? 1 : n <= 65535 ? 2 : 4;
    EXPECT_EQ(a.bytes(), a.points() * (sizeof(float) + indexBytes)) << n;
  }
}

TEST(AliasTable1D, ProbabilitiesAreFloatRoundedExactValues) {
  const auto v = fixture1D(Fixture::PeakedSun);
  const AliasTable1D t(v);
  const auto exact = exactCellProbabilities(v);
  for (uint32_t i = 0; i < kCells; ++i) ASSERT_NEAR(t.table().probability(i), exact[i], 1e-6 * exact[i]) << i;
  EXPECT_EQ(t.bytes(), kCells * 12u);
}

TEST(PiecewiseConstant1D, CdfIsNormalisedAndMonotone) {
  for (Fixture f : kAllFixtures) {
    const PiecewiseConstant1D p(fixture1D(f));
    const auto cdf = p.cdf();
    ASSERT_EQ(cdf.size(), kCells + 1);
    EXPECT_EQ(cdf.front(), 0.0f);
    EXPECT_EQ(cdf.back(), 1.0f);
    EXPECT_TRUE(std::is_sorted(cdf.begin(), cdf.end())) << toString(f);
    const auto v = fixture1D(f);
    EXPECT_NEAR(p.integral(), std::accumulate(v.begin(), v.end(), 0.0) / kCells, 1e-9 * p.integral());
  }
}

}  // namespace
