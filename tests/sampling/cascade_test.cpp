// Cascade: chi-square in 2D, 3D and 4D with conditioning dimensions, uniform / adaptive / mixed
// dimension methods, both conditional rules, both simplifiers and both error metrics; invert,
// cell probabilities, structure, slices, threads and build determinism. The domain contract
// (samples inside, pdf(sample) = returned pdf, ∫pdf = 1, pdf 0 outside): domain_contract_test.cpp.

#include "acdf/sampling/cascade.h"
#include "acdf/sampling/adaptive_cdf_1d.h"
#include "acdf/sampling/alias_grid.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "acdf/sampling/quality.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/simplify.h"
#include "acdf/test_support/chi_square_harness.h"
#include "acdf/test_support/samplers.h"

namespace {

using namespace acdf;
using namespace acdf::test_support;
using DM = DimensionMethod;

const std::vector<uint32_t> k2D = {64, 32};
const std::vector<uint32_t> k3D = {16, 8, 12};
const std::vector<uint32_t> k4D = {8, 4, 32, 16};  // 8×4 conditioning × 32×16 sampled

CascadeOptions withMethods(std::vector<DM> methods, uint32_t conditioning = 0) {
  CascadeOptions o;
  o.conditioningDims = conditioning;
  o.methods = std::move(methods);
  return o;
}

// ---- Every fixture × shape × method set ---------------------------------------------------

struct Shape {
  std::string name;
  std::vector<uint32_t> dims;
  std::vector<DM> methods;  // empty: all adaptive (the default)
};

const std::vector<Shape>& shapes() {
  static const std::vector<Shape> s = {
      {"2D_Uniform", k2D, {DM::Uniform, DM::Uniform}},
      {"2D_Adaptive", k2D, {}},
      {"3D_Adaptive", k3D, {DM::Adaptive, DM::Adaptive, DM::Adaptive}},
      {"3D_MixedAUA", k3D, {DM::Adaptive, DM::Uniform, DM::Adaptive}},
  };
  return s;
}

using ShapeParam = std::tuple<int, Fixture>;

class CascadeFixtures : public ::testing::TestWithParam<ShapeParam> {
 protected:
  const Shape& shape() const { return shapes()[std::get<0>(GetParam())]; }
  std::vector<float> values() const { return makeFixture(std::get<1>(GetParam()), shape().dims); }
  Sampler sampler() const {
    const auto v = values();
    return makeCascade(v, unitAxes(shape().dims), withMethods(shape().methods));
  }
};

ACDF_CHI_SQUARE_TEST_P(CascadeFixtures, ChiSquare, 1) {
  const ChiSquareReport r = runChiSquare(sampler(), ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r));
}

TEST_P(CascadeFixtures, InvertRecoversTheVariates) {
  const Sampler s = sampler();
  EXPECT_LE(worstInvertError(s, 50'000, 17), 1e-4);
}

TEST_P(CascadeFixtures, CellProbabilitiesSumToOneAndMatchPdf) {
  const Sampler s = sampler();
  const auto q = s.cellProbabilities();
  const auto fromPdf = pdfCellProbabilities(s.axes, s.pdf);
  ASSERT_EQ(q.size(), fromPdf.size());
  EXPECT_NEAR(std::accumulate(q.begin(), q.end(), 0.0), 1.0, 1e-6);
  for (std::size_t i = 0; i < q.size(); ++i) ASSERT_NEAR(fromPdf[i], q[i], 2e-6 * q[i] + 1e-30) << "cell " << i;
}

INSTANTIATE_TEST_SUITE_P(AllFixtures, CascadeFixtures,
                         ::testing::Combine(::testing::Range(0, 4), ::testing::ValuesIn(kAllFixtures)),
                         [](const auto& info) {
                           return shapes()[std::get<0>(info.param)].name + "_" + toString(std::get<1>(info.param));
                         });

class CascadeUniformExact : public ::testing::TestWithParam<Fixture> {};

TEST_P(CascadeUniformExact, CellProbabilitiesAreTheFunctions) {
  // With every dimension uniform nothing is simplified, so ExactMass reproduces value / Σ up to
  // the float CDFs' rounding (a few 1e-7 absolute per level).
  for (const std::vector<uint32_t>& dims : {k2D, k3D}) {
    const auto v = makeFixture(GetParam(), dims);
    const Sampler s = makeCascade(v, unitAxes(dims), withMethods(std::vector<DM>(dims.size(), DM::Uniform)));
    const auto q = s.cellProbabilities();
    const auto exact = exactCellProbabilities(v);
    for (std::size_t i = 0; i < q.size(); ++i) ASSERT_NEAR(q[i], exact[i], 3e-7 + 1e-5 * exact[i]) << "cell " << i;
    EXPECT_LT(compareCellProbabilities(exact, q).chi2Divergence, 1e-4);
  }
}

INSTANTIATE_TEST_SUITE_P(AllFixtures, CascadeUniformExact, ::testing::ValuesIn(kAllFixtures),
                         [](const auto& info) { return toString(info.param); });

// ---- 4D: 8×4 conditioning × 32×16 sampled ------------------------------------------------------

// The conditioning coordinates of the two slices tested per fixture: cell (1, 0), inside the
// islands of zerosWithIslands, and cell (7, 2), where zerosWithIslands is all zero.
const std::vector<std::vector<float>> kConditions = {{0.13f, 0.1f}, {0.93f, 0.6f}};

std::vector<float> sliceValues(const std::vector<float>& values, std::size_t slice) {
  const std::size_t n = std::size_t(k4D[2]) * k4D[3];
  return {values.begin() + static_cast<std::ptrdiff_t>(slice * n),
          values.begin() + static_cast<std::ptrdiff_t>((slice + 1) * n)};
}

class CascadeConditioned : public ::testing::TestWithParam<std::tuple<Fixture, int>> {
 protected:
  Fixture fixture() const { return std::get<0>(GetParam()); }
  const std::vector<float>& condition() const { return kConditions[std::get<1>(GetParam())]; }
  std::shared_ptr<const Cascade> cascade(std::vector<DM> methods = {}) const {
    const auto v = makeFixture(fixture(), k4D);
    return std::make_shared<const Cascade>(v, unitAxes(k4D), withMethods(std::move(methods), 2));
  }
};

ACDF_CHI_SQUARE_TEST_P(CascadeConditioned, ChiSquareOfTheSlice, 1) {
  const Sampler s = makeCascade(cascade(), condition());
  ASSERT_EQ(s.axes.size(), 2u);
  const ChiSquareReport r = runChiSquare(s, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r));
}

TEST_P(CascadeConditioned, SliceEqualsAStandaloneCascadeOfItsValues) {
  for (const std::vector<DM>& methods : {std::vector<DM>{}, std::vector<DM>{DM::Uniform, DM::Adaptive}}) {
    const auto c = cascade(methods);
    const std::size_t slice = c->sliceOf(condition());
    const auto v = makeFixture(fixture(), k4D);
    const auto own = sliceValues(v, slice);
    const Cascade alone(own, unitAxes(std::vector<uint32_t>{k4D[2], k4D[3]}), withMethods(methods));
    const auto q = c->cellProbabilities(slice), expected = alone.cellProbabilities(0);
    ASSERT_EQ(q.size(), expected.size());
    for (std::size_t i = 0; i < q.size(); ++i) ASSERT_NEAR(q[i], expected[i], 1e-12) << "cell " << i;
    const double volume = (1.0 / k4D[2]) * (1.0 / k4D[3]);
    EXPECT_NEAR(c->integral(slice), std::accumulate(own.begin(), own.end(), 0.0) * volume,
                1e-9 * c->integral(slice) + 1e-300);
    EXPECT_EQ(c->isUniformFallback(slice), std::all_of(own.begin(), own.end(), [](float x) { return x == 0; }));
  }
}

TEST_P(CascadeConditioned, InvertAndCellProbabilities) {
  const auto c = cascade();
  const Sampler s = makeCascade(c, condition());
  const auto q = s.cellProbabilities();
  EXPECT_NEAR(std::accumulate(q.begin(), q.end(), 0.0), 1.0, 1e-6);
  const auto fromPdf = pdfCellProbabilities(s.axes, s.pdf);
  for (std::size_t i = 0; i < q.size(); ++i) ASSERT_NEAR(fromPdf[i], q[i], 2e-6 * q[i] + 1e-30) << i;
  EXPECT_LE(worstInvertError(s, 20'000, 23), 1e-4);
}

INSTANTIATE_TEST_SUITE_P(AllFixtures, CascadeConditioned,
                         ::testing::Combine(::testing::ValuesIn(kAllFixtures), ::testing::Values(0, 1)),
                         [](const auto& info) {
                           return toString(std::get<0>(info.param)) + "_slice" +
                                  std::to_string(std::get<1>(info.param));
                         });

ACDF_CHI_SQUARE_TEST(CascadeConditioning, FourSampledDimensionsWithoutConditioning, 1) {
  const std::vector<uint32_t> dims = {8, 4, 8, 4};
  const auto v = makeFixture(Fixture::Checkerboard, dims);
  const Sampler s =
      makeCascade(v, unitAxes(dims), withMethods({DM::Adaptive, DM::Uniform, DM::Adaptive, DM::Adaptive}));
  const ChiSquareReport r = runChiSquare(s, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r));
}

TEST(CascadeConditioning, SamplePointFeedsPdfAndInvert) {
  // SampleND::point() holds exactly the sampled coordinates, so pdf(condition, s.point()) works
  // without slicing the fixed-size array by hand.
  const auto v = makeFixture(Fixture::Random, k4D);
  const Cascade c(v, unitAxes(k4D), withMethods({}, 2));
  const float condition[] = {0.3f, 0.6f}, u[] = {0.25f, 0.75f};
  const SampleND s = c.sample(condition, u);
  ASSERT_EQ(s.point().size(), c.sampledDims());
  EXPECT_EQ(c.pdf(condition, s.point()), s.pdf);
  float back[2];
  c.invert(condition, s.point(), back);
  EXPECT_NEAR(back[0], u[0], 1e-5);
  EXPECT_NEAR(back[1], u[1], 1e-5);
  const AliasGrid alias(makeFixture(Fixture::Random, k2D), unitAxes(k2D));
  const SampleND a = alias.sample(u);
  ASSERT_EQ(a.point().size(), 2u);
  EXPECT_EQ(alias.pdf(a.point()), a.pdf);
}

TEST(CascadeConditioning, SliceLookupIsTheNearestCell) {
  const auto v = makeFixture(Fixture::Random, k4D);
  const Cascade c(v, unitAxes(k4D), withMethods({}, 2));
  EXPECT_EQ(c.slices(), 32u);
  EXPECT_EQ(c.conditioningDims(), 2u);
  EXPECT_EQ(c.sampledDims(), 2u);
  for (uint32_t i = 0; i < 8; ++i)
    for (uint32_t j = 0; j < 4; ++j) {
      const float cond[] = {(i + 0.5f) / 8, (j + 0.5f) / 4};
      EXPECT_EQ(c.sliceOf(cond), i * 4 + j);
    }
  const float outside[] = {-5.0f, 99.0f};
  EXPECT_EQ(c.sliceOf(outside), 3u);  // clamped to cell (0, 3)
  // A slice given directly is the slice of its condition.
  const float cond[] = {0.7f, 0.3f}, u[] = {0.35f, 0.8f};
  const SampleND bySlice = c.sampleInSlice(5 * 4 + 1, u), byCondition = c.sample(cond, u);
  EXPECT_EQ(bySlice.x[0], byCondition.x[0]);
  EXPECT_EQ(bySlice.x[1], byCondition.x[1]);
  EXPECT_EQ(bySlice.pdf, byCondition.pdf);
  EXPECT_EQ(c.pdfInSlice(5 * 4 + 1, bySlice.point()), c.pdf(cond, bySlice.point()));
  EXPECT_THROW(c.sampleInSlice(c.slices(), u), std::out_of_range);
  EXPECT_THROW(c.pdfInSlice(c.slices(), u), std::out_of_range);
  // Different slices are different distributions.
  const float a[] = {0.1f, 0.1f}, b[] = {0.9f, 0.9f}, x[] = {0.3f, 0.3f};
  EXPECT_NE(c.pdf(a, x), c.pdf(b, x));
}

TEST(CascadeConditioning, PdfOfCellsIsThePdfInThoseCells) {
  // pdfOfCellsInSlice at a cell is pdfInSlice at any point of it (its lowest and highest floats
  // and its centre) and the cell's probability over its volume, in every slice; uniform, adaptive
  // and mixed levels, on shifted axes, with zero cells among them (ZerosWithIslands).
  struct Setup {
    std::vector<GridAxis> axes;
    uint32_t conditioning;
    std::vector<DM> methods;
    Fixture fixture;
  };
  const std::vector<GridAxis> axes4D = {GridAxis(3, 0.0f, 1.0f), GridAxis(2, -1.0f, 1.0f), GridAxis(24, 0.0f, 2.0f),
                                        GridAxis(10, -3.0f, 5.0f)};
  const std::vector<GridAxis> axes3D = {GridAxis(4, 0.0f, 1.0f), GridAxis(16, 10.0f, 12.0f),
                                        GridAxis(12, -1.0f, -0.5f)};
  const std::vector<Setup> setups = {{axes4D, 2, {DM::Uniform, DM::Uniform}, Fixture::Random},
                                     {axes4D, 2, {DM::Adaptive, DM::Adaptive}, Fixture::Random},
                                     {axes4D, 2, {DM::Adaptive, DM::Adaptive}, Fixture::ZerosWithIslands},
                                     {axes3D, 1, {DM::Adaptive, DM::Uniform}, Fixture::Smooth},
                                     {axes3D, 1, {DM::Uniform, DM::Adaptive}, Fixture::ZerosWithIslands}};
  for (const Setup& setup : setups) {
    std::vector<uint32_t> dims;
    for (const GridAxis& a : setup.axes) dims.push_back(a.cells());
    CascadeOptions options = withMethods(setup.methods, setup.conditioning);
    options.simplify.epsilon = 0.01;
    const Cascade c(makeFixture(setup.fixture, dims), setup.axes, options);
    const GridAxis &rows = setup.axes[setup.conditioning], &columns = setup.axes[setup.conditioning + 1];
    const double volume = rows.cellWidth() * columns.cellWidth();
    const auto pointsOf = [](const GridAxis& axis, uint32_t cell) {
      return std::array<float, 3>{axis.place(cell, cell + 1, 0.0), axis.place(cell, cell + 1, 0.5),
                                  axis.place(cell, cell + 1, 1.0)};
    };
    std::size_t zeros = 0;
    for (std::size_t slice = 0; slice < c.slices(); ++slice) {
      const std::vector<double> q = c.cellProbabilities(slice);
      for (uint32_t i = 0; i < rows.cells(); ++i)
        for (uint32_t j = 0; j < columns.cells(); ++j) {
          const uint32_t cells[] = {i, j};
          const float p = c.pdfOfCellsInSlice(slice, cells);
          const double expected = q[i * columns.cells() + j];
          zeros += p == 0.0f;
          ASSERT_NEAR(p * volume, expected, 1e-6 * expected + 1e-30) << "slice " << slice << " cell " << i << ", " << j;
          for (float x0 : pointsOf(rows, i))
            for (float x1 : pointsOf(columns, j)) {
              const float x[] = {x0, x1};
              ASSERT_EQ(c.pdfInSlice(slice, x), p) << "slice " << slice << " at " << x0 << ", " << x1;
            }
        }
    }
    if (setup.fixture == Fixture::ZerosWithIslands) {
      EXPECT_GT(zeros, 0u);
    }
    const uint32_t outside[] = {rows.cells(), 0}, alsoOutside[] = {0, columns.cells()}, tooFew[] = {0};
    EXPECT_EQ(c.pdfOfCellsInSlice(0, outside), 0.0f);
    EXPECT_EQ(c.pdfOfCellsInSlice(0, alsoOutside), 0.0f);
    EXPECT_THROW(c.pdfOfCellsInSlice(c.slices(), tooFew), std::out_of_range);
    EXPECT_THROW(c.pdfOfCellsInSlice(0, tooFew), std::invalid_argument);
  }
}

TEST(CascadeConditioning, SampleCellsAreTheCellsOfTheSampleWithTheirPdf) {
  // sampleCellsInSlice is sampleInSlice's point, its cells, where in them it lies and the cells'
  // pdf bit for bit, in every slice, on random variates and the extreme ones; uniform and adaptive
  // levels on shifted axes.
  const std::vector<GridAxis> axes = {GridAxis(4, 0.0f, 1.0f), GridAxis(16, 10.0f, 12.0f), GridAxis(12, -1.0f, -0.5f)};
  for (const std::vector<DM>& methods : {std::vector<DM>{DM::Uniform, DM::Uniform}, {DM::Adaptive, DM::Adaptive}}) {
    CascadeOptions options = withMethods(methods, 1);
    options.simplify.epsilon = 0.01;
    const std::vector<uint32_t> dims = {4, 16, 12};
    const Cascade c(makeFixture(Fixture::ZerosWithIslands, dims), axes, options);
    Pcg32 rng(3);
    for (std::size_t slice = 0; slice < c.slices(); ++slice)
      for (int n = 0; n < 2000; ++n) {
        const float u[] = {n < 4 ? (n & 1 ? kOneMinusEpsilon : 0.0f) : rng.nextFloat(),
                           n < 4 ? (n & 2 ? kOneMinusEpsilon : 0.0f) : rng.nextFloat()};
        const SampleND s = c.sampleInSlice(slice, u);
        const CellSample cells = c.sampleCellsInSlice(slice, u);
        ASSERT_EQ(cells.dims, 2u);
        ASSERT_EQ(cells.pdf, s.pdf);
        for (std::size_t d = 0; d < 2; ++d) {
          const GridAxis& axis = axes[1 + d];
          ASSERT_EQ(cells.x[d], s.x[d]);
          ASSERT_EQ(cells.cells[d], axis.cellOf(s.x[d])) << "slice " << slice << " u " << u[0] << ", " << u[1];
          ASSERT_TRUE(cells.fractions[d] >= 0.0 && cells.fractions[d] < 1.0) << cells.fractions[d];
          ASSERT_NEAR(axis.lo() + (cells.cells[d] + cells.fractions[d]) * axis.cellWidth(), s.x[d], 1e-12);
        }
        ASSERT_EQ(c.pdfOfCellsInSlice(slice, std::span<const uint32_t>(cells.cells.data(), 2)), cells.pdf);
      }
  }
}

TEST(CascadeConditioning, AllZeroSliceIsUniform) {
  const auto v = makeFixture(Fixture::ZerosWithIslands, k4D);
  const auto c = std::make_shared<const Cascade>(v, unitAxes(k4D), withMethods({}, 2));
  const std::size_t slice = c->sliceOf(kConditions[1]);
  ASSERT_TRUE(c->isUniformFallback(slice));
  const Sampler s = makeCascade(c, kConditions[1]);
  for (float x : {0.01f, 0.5f, 0.99f}) {
    const float p[] = {x, 1 - x};
    EXPECT_NEAR(s.pdf(p), 1.0f, 1e-6f);
  }
  for (double q : s.cellProbabilities()) ASSERT_NEAR(q, 1.0 / (32 * 16), 1e-9);
}

// ---- Options: conditional rule, simplifier, metric, weight bound, budget ---------------------

struct Variant {
  std::string name;
  CascadeOptions options;
  Fixture fixture;
};

std::vector<Variant> variants() {
  std::vector<Variant> out;
  CascadeOptions o;
  o.conditional = ConditionalRule::AverageOfNormalized;
  for (Fixture f : {Fixture::Smooth, Fixture::Random, Fixture::ZerosWithIslands})
    out.push_back({"AverageOfNormalized_" + toString(f), o, f});
  o = {};
  o.simplify.method = Simplifier::GreedyRefinement;
  out.push_back({"Greedy_random", o, Fixture::Random});
  out.push_back({"Greedy_checkerboard", o, Fixture::Checkerboard});
  o = {};
  o.simplify.metric = ErrorMetric::Perpendicular;
  out.push_back({"Perpendicular_peakedSun", o, Fixture::PeakedSun});
  out.push_back({"Perpendicular_smooth", o, Fixture::Smooth});
  o = {};
  o.simplify.method = Simplifier::GreedyRefinement;
  o.simplify.metric = ErrorMetric::Perpendicular;
  o.simplify.maxPoints = 6;
  o.simplify.epsilon = 0;
  out.push_back({"GreedyPerpendicularBudget6_random", o, Fixture::Random});
  o = {};
  o.simplify.epsilon = 0.05;
  o.simplify.weightBound = 0;
  o.conditional = ConditionalRule::AverageOfNormalized;
  out.push_back({"CoarseNoWeightBoundAverage_zerosWithIslands", o, Fixture::ZerosWithIslands});
  o = {};
  o.tolerance = ConditionalTolerance::MassScaled;
  out.push_back({"MassScaled_peakedSun", o, Fixture::PeakedSun});
  out.push_back({"MassScaled_random", o, Fixture::Random});
  o.simplify.metric = ErrorMetric::ChiSquare;
  o.simplify.epsilon = 1e-4;
  out.push_back({"ChiSquareMassScaled_peakedSun", o, Fixture::PeakedSun});
  o = {};
  o.simplify.method = Simplifier::GreedyRefinement;
  o.simplify.metric = ErrorMetric::ChiSquare;
  o.simplify.epsilon = 1e-3;
  o.simplify.weightBound = 0;
  out.push_back({"GreedyChiSquareNoWeightBound_zerosWithIslands", o, Fixture::ZerosWithIslands});
  return out;
}

class CascadeOptionsTest : public ::testing::TestWithParam<int> {};

ACDF_CHI_SQUARE_TEST_P(CascadeOptionsTest, ChiSquareAndConsistency, 1) {
  const Variant v = variants()[GetParam()];
  const auto values = makeFixture(v.fixture, k2D);
  const Sampler s = makeCascade(values, unitAxes(k2D), v.options);
  const ChiSquareReport r = runChiSquare(s, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r)) << v.name;
  const auto q = s.cellProbabilities();
  EXPECT_NEAR(std::accumulate(q.begin(), q.end(), 0.0), 1.0, 1e-6);
  const auto fromPdf = pdfCellProbabilities(s.axes, s.pdf);
  for (std::size_t i = 0; i < q.size(); ++i) ASSERT_NEAR(fromPdf[i], q[i], 2e-6 * q[i] + 1e-30) << i;
}

INSTANTIATE_TEST_SUITE_P(Variants, CascadeOptionsTest, ::testing::Range(0, int(variants().size())),
                         [](const auto& info) { return variants()[info.param].name; });

TEST(CascadeOptions, ExactMassConditionalKeepsBlockMasses) {
  // Level 0 adaptive (rows merged into intervals), level 1 uniform. With ExactMass the
  // conditional below an interval is Σ_rows f / Σ_block f, so for every interval I and column j
  // Σ_{rows in I} q(row, j) equals the function's mass of (I, j). AverageOfNormalized averages
  // normalised row conditionals instead and misses it on rows of different totals.
  const auto v = makeFixture(Fixture::Random, k2D);
  const uint32_t rows = k2D[0], cols = k2D[1];
  CascadeOptions exact = withMethods({DM::Adaptive, DM::Uniform});
  exact.simplify.epsilon = 0.02;
  // Without the weight bound level 0 keeps exactly the 1D simplification's intervals (the bound
  // may refine them to protect whole cells, which is tested in weight_bound_test.cpp).
  exact.simplify.weightBound = 0.0;
  CascadeOptions average = exact;
  average.conditional = ConditionalRule::AverageOfNormalized;
  const Cascade a(v, unitAxes(k2D), exact), b(v, unitAxes(k2D), average);

  // The row marginal's CDF, simplified with the same options, gives level 0's intervals.
  std::vector<double> rowMass(rows, 0.0);
  for (uint32_t i = 0; i < rows; ++i)
    for (uint32_t j = 0; j < cols; ++j) rowMass[i] += v[i * cols + j];
  const double total = std::accumulate(rowMass.begin(), rowMass.end(), 0.0);
  std::vector<float> cdf(rows + 1, 0.0f);
  double running = 0;
  for (uint32_t i = 0; i < rows; ++i) cdf[i + 1] = static_cast<float>((running += rowMass[i]) / total);
  cdf.back() = 1.0f;
  const auto kept = simplifyCdf(cdf, exact.simplify);
  ASSERT_EQ(a.pointsPerDimension()[0], kept.size());
  ASSERT_LT(kept.size(), rows + 1u) << "level 0 must merge rows for the rules to differ";
  EXPECT_EQ(a.breakpoints(0), std::vector<std::vector<uint32_t>>{kept});
  std::vector<uint32_t> everyColumn(cols + 1);
  std::iota(everyColumn.begin(), everyColumn.end(), 0u);
  EXPECT_EQ(a.breakpoints(1), std::vector<std::vector<uint32_t>>(kept.size() - 1, everyColumn)) << "uniform level";

  const auto exactP = exactCellProbabilities(v);
  const auto qa = a.cellProbabilities(0), qb = b.cellProbabilities(0);
  double worstA = 0, worstB = 0;
  for (std::size_t k = 0; k + 1 < kept.size(); ++k)
    for (uint32_t j = 0; j < cols; ++j) {
      double want = 0, gotA = 0, gotB = 0;
      for (uint32_t i = kept[k]; i < kept[k + 1]; ++i) {
        want += exactP[i * cols + j];
        gotA += qa[i * cols + j];
        gotB += qb[i * cols + j];
      }
      worstA = std::max(worstA, std::abs(gotA - want) / want);
      worstB = std::max(worstB, std::abs(gotB - want) / want);
    }
  EXPECT_LT(worstA, 1e-4) << "ExactMass block masses";
  EXPECT_GT(worstB, 1e-3) << "AverageOfNormalized should differ on rows of different totals";
}

// The smooth 2D fixture with both levels adaptive and simplified (ε = 0.01).
Cascade simplifiedSmoothCascade() {
  CascadeOptions options;
  options.simplify.epsilon = 0.01;
  return Cascade(makeFixture(Fixture::Smooth, k2D), unitAxes(k2D), options);
}

TEST(Cascade, BreakpointsBoundTheBoxesOfConstantDensity) {
  // Both levels adaptive: CDF k of level 1 is the conditional below interval k of level 0, so
  // every box (level-0 interval × one of its conditional's intervals) has one cell probability.
  const Cascade c = simplifiedSmoothCascade();
  const auto rowsKept = c.breakpoints(0), columnsKept = c.breakpoints(1);
  ASSERT_EQ(rowsKept.size(), 1u);
  ASSERT_EQ(columnsKept.size(), rowsKept[0].size() - 1);
  std::size_t points = 0;
  for (const auto& cdf : columnsKept) points += cdf.size();
  EXPECT_EQ(points, c.pointsPerDimension()[1]);
  const uint32_t cols = k2D[1];
  const auto q = c.cellProbabilities(0);
  std::size_t boxes = 0;
  for (std::size_t k = 0; k + 1 < rowsKept[0].size(); ++k) {
    const auto& col = columnsKept[k];
    ASSERT_EQ(col.front(), 0u);
    ASSERT_EQ(col.back(), cols);
    for (std::size_t m = 0; m + 1 < col.size(); ++m, ++boxes) {
      const double first = q[rowsKept[0][k] * cols + col[m]];
      for (uint32_t i = rowsKept[0][k]; i < rowsKept[0][k + 1]; ++i)
        for (uint32_t j = col[m]; j < col[m + 1]; ++j)
          ASSERT_NEAR(q[i * cols + j], first, 1e-6 * first) << "box " << k << "," << m << " cell " << i << "," << j;
    }
  }
  EXPECT_LT(boxes, std::size_t{k2D[0]} * cols / 4) << "the fixture should be simplified";
  EXPECT_THROW(c.breakpoints(2), std::invalid_argument);
}

TEST(Cascade, BreakpointValuesGiveEveryBoxItsMass) {
  // A box's probability is the product of its intervals' value steps: what a caller that samples
  // the table in its own arithmetic (the Mitsuba plugin) relies on.
  const Cascade c = simplifiedSmoothCascade();
  const auto rows = c.breakpoints(0), columns = c.breakpoints(1);
  const auto rowValues = c.breakpointValues(0), columnValues = c.breakpointValues(1);
  ASSERT_EQ(rowValues.size(), rows.size());
  ASSERT_EQ(columnValues.size(), columns.size());
  const uint32_t cols = k2D[1];
  const auto q = c.cellProbabilities(0);
  for (std::size_t k = 0; k + 1 < rows[0].size(); ++k) {
    ASSERT_EQ(columnValues[k].size(), columns[k].size());
    EXPECT_EQ(columnValues[k].front(), 0.0f);
    EXPECT_EQ(columnValues[k].back(), 1.0f);
    const double rowMass = static_cast<double>(rowValues[0][k + 1]) - rowValues[0][k];
    for (std::size_t m = 0; m + 1 < columns[k].size(); ++m) {
      double box = 0;
      for (uint32_t i = rows[0][k]; i < rows[0][k + 1]; ++i)
        for (uint32_t j = columns[k][m]; j < columns[k][m + 1]; ++j) box += q[i * cols + j];
      const double mass = rowMass * (static_cast<double>(columnValues[k][m + 1]) - columnValues[k][m]);
      ASSERT_NEAR(mass, box, 1e-6 * box + 1e-12) << "box " << k << "," << m;
    }
  }
  EXPECT_THROW(c.breakpointValues(2), std::invalid_argument);
}

TEST(CascadeOptions, EnumSpellingsRoundTrip) {
  for (DimensionMethod m : {DimensionMethod::Uniform, DimensionMethod::Adaptive})
    EXPECT_EQ(parseDimensionMethod(toString(m)), m);
  for (ConditionalRule r : {ConditionalRule::ExactMass, ConditionalRule::AverageOfNormalized})
    EXPECT_EQ(parseConditionalRule(toString(r)), r);
  for (ConditionalTolerance t : {ConditionalTolerance::Constant, ConditionalTolerance::MassScaled})
    EXPECT_EQ(parseConditionalTolerance(toString(t)), t);
  EXPECT_THROW(parseDimensionMethod("Adaptive"), std::invalid_argument);
  EXPECT_THROW(parseConditionalRule("exact"), std::invalid_argument);
  EXPECT_THROW(parseConditionalTolerance(""), std::invalid_argument);
}

TEST(CascadeOptions, MetricAndSimplifierChangeTheResult) {
  const auto v = makeFixture(Fixture::Smooth, k2D);
  CascadeOptions vertical, perpendicular, greedy;
  vertical.simplify.epsilon = perpendicular.simplify.epsilon = greedy.simplify.epsilon = 1e-4;
  vertical.simplify.weightBound = perpendicular.simplify.weightBound = greedy.simplify.weightBound = 0;
  perpendicular.simplify.metric = ErrorMetric::Perpendicular;
  greedy.simplify.method = Simplifier::GreedyRefinement;
  greedy.simplify.maxPoints = 4;
  const Cascade a(v, unitAxes(k2D), vertical), b(v, unitAxes(k2D), perpendicular), c(v, unitAxes(k2D), greedy);
  EXPECT_NE(a.pointsPerDimension(), b.pointsPerDimension());
  // A budget of 4 points per 1D CDF: 4 points at level 0, 3 intervals × 4 points at level 1.
  EXPECT_EQ(c.pointsPerDimension(), (std::vector<std::size_t>{4, 12}));
}

TEST(CascadeOptions, MassScaledToleranceMatchesAStandaloneConditional) {
  // Level 0 keeps ε; the conditional below an interval of share P is the 1D CDF of that
  // interval's (exact-mass) row sums simplified with ε/√P (at most 1/2) for the CDF distances,
  // ε/P (at most cells − 1) for the χ² metric, whose contributions reach the joint divergence
  // scaled by P rather than P².
  const auto v = makeFixture(Fixture::PeakedSun, k2D);
  const uint32_t rows = k2D[0], cols = k2D[1];
  double total = 0.0;
  for (float x : v) total += x;
  for (ErrorMetric metric : {ErrorMetric::Vertical, ErrorMetric::ChiSquare}) {
    const bool chiSquare = metric == ErrorMetric::ChiSquare;
    CascadeOptions o;
    o.tolerance = ConditionalTolerance::MassScaled;
    o.simplify.metric = metric;
    o.simplify.epsilon = chiSquare ? 1e-5 : 2e-3;
    o.simplify.weightBound = 0;
    o.methods = {DM::Uniform, DM::Adaptive};  // one conditional per row: share = the row's mass
    const Cascade mass(v, unitAxes(k2D), o);
    o.tolerance = ConditionalTolerance::Constant;
    const Cascade constant(v, unitAxes(k2D), o);
    const double loosest = chiSquare ? cols - 1.0 : 0.5;
    std::size_t expectedPoints = 0;
    for (uint32_t r = 0; r < rows; ++r) {
      const std::span<const float> row(v.data() + std::size_t{r} * cols, cols);
      double rowMass = 0.0;
      for (float x : row) rowMass += x;
      const double share = rowMass / total;
      SimplifyOptions so = o.simplify;
      so.epsilon = rowMass > 0 ? std::min(loosest, so.epsilon / (chiSquare ? share : std::sqrt(share))) : loosest;
      expectedPoints += AdaptiveCdf1D(row, 0.0f, 1.0f, so).points();
    }
    EXPECT_EQ(mass.pointsPerDimension()[1], expectedPoints) << toString(metric);
    EXPECT_LT(mass.pointsPerDimension()[1], constant.pointsPerDimension()[1]) << toString(metric);
    EXPECT_EQ(mass.pointsPerDimension()[0], constant.pointsPerDimension()[0]) << toString(metric);
  }
}

// Fails on an engine that bounds each 1D CDF only: rows merged below an interval then give whole
// cells less than 1/ρ of their probability (e.g. checkerboard at ε = 0.3, ρ = 1.5).
TEST(CascadeOptions, WeightBoundHoldsForWholeCells) {
  // simplify.h: a Cascade applies ρ to whole grid cells: p(cell) / q(cell) <= ρ, where p is the
  // function's cell probability and q the cascade's, up to the float CDFs' resolution (2^-22
  // absolute on a conditional probability, so tiny cells may exceed it slightly).
  for (Fixture f : kAllFixtures)
    for (const std::vector<uint32_t>& dims : {k2D, k3D})
      for (double rho : {1.5, 2.0, 4.0})
        for (double eps : {0.02, 0.3}) {
          CascadeOptions o;
          o.simplify.weightBound = rho;
          o.simplify.epsilon = eps;
          const auto v = makeFixture(f, dims);
          const Cascade c(v, unitAxes(dims), o);
          const auto p = exactCellProbabilities(v);
          const auto q = c.cellProbabilities(0);
          double worst = 0;
          for (std::size_t i = 0; i < p.size(); ++i) {
            ASSERT_TRUE(p[i] == 0 || q[i] > 0) << toString(f) << " cell " << i << " unreachable";
            if (p[i] > 0) {
              ASSERT_LE(p[i], rho * q[i] * (1 + 1e-6) + rho * 0x1p-22)
                  << toString(f) << " rho " << rho << " cell " << i;
            }
            if (p[i] > 1e-4) worst = std::max(worst, p[i] / q[i]);
          }
          EXPECT_LE(worst, rho * 1.01) << toString(f) << " " << dims.size() << "D rho " << rho << " eps " << eps;
        }
  // Without the bound a coarse ε leaves much larger ratios: the check above is not vacuous.
  CascadeOptions loose;
  loose.simplify.weightBound = 0;
  loose.simplify.epsilon = 0.3;
  const auto v = makeFixture(Fixture::ZerosWithIslands, k2D);
  const auto q = Cascade(v, unitAxes(k2D), loose).cellProbabilities(0);
  EXPECT_GT(compareCellProbabilities(exactCellProbabilities(v), q).maxWeightRatio, 4.0);
}

// ---- Structure --------------------------------------------------------------------------------

TEST(CascadeStructure, UniformLevelsStoreEveryInnerVertex) {
  const auto v = makeFixture(Fixture::Smooth, k2D);
  const Cascade c(v, unitAxes(k2D), withMethods({DM::Uniform, DM::Uniform}));
  EXPECT_EQ(c.averageIntervals(), (std::vector<double>{64, 32}));
  EXPECT_EQ(c.pointsPerDimension(), (std::vector<std::size_t>{65, 64 * 33}));
  // The end points 0 and 1 of every CDF are implicit.
  EXPECT_GE(c.bytes(), (63 + 64 * 31) * sizeof(float));
  EXPECT_LT(c.bytes(), (63 + 64 * 31) * sizeof(float) + 1024);
}

TEST(CascadeStructure, EndPointsAreImplicit) {
  // A constant function keeps only the end points of each 1D CDF: nothing is stored for them but
  // each CDF's offset (two per level, with the end) and the slice integral.
  const std::vector<float> v(64 * 32, 1.0f);
  const Cascade c(v, unitAxes(k2D));
  EXPECT_EQ(c.pointsPerDimension(), (std::vector<std::size_t>{2, 2}));
  EXPECT_EQ(c.averageIntervals(), (std::vector<double>{1, 1}));
  EXPECT_EQ(c.bytes(), sizeof(double) + 2 * 2 * sizeof(uint32_t));
  const std::array<float, 2> u{0.25f, 0.75f};
  const SampleND x = c.sample(u);
  EXPECT_FLOAT_EQ(x.x[0], 0.25f);
  EXPECT_FLOAT_EQ(x.x[1], 0.75f);
  EXPECT_FLOAT_EQ(x.pdf, 1.0f);
}

TEST(CascadeStructure, ConditionedUniformLevels) {
  const auto v = makeFixture(Fixture::Smooth, k4D);
  const Cascade c(v, unitAxes(k4D), withMethods({DM::Uniform, DM::Uniform}, 2));
  EXPECT_EQ(c.averageIntervals(), (std::vector<double>{8, 4, 32, 16}));
  EXPECT_EQ(c.pointsPerDimension(), (std::vector<std::size_t>{32 * 33, 32 * 32 * 17}));
}

TEST(CascadeStructure, AdaptiveLevelsCompress) {
  const auto v = makeFixture(Fixture::Smooth, k3D);
  const Cascade adaptive(v, unitAxes(k3D));
  const Cascade uniform(v, unitAxes(k3D), withMethods({DM::Uniform, DM::Uniform, DM::Uniform}));
  const auto intervals = adaptive.averageIntervals();
  ASSERT_EQ(intervals.size(), 3u);
  for (std::size_t d = 0; d < 3; ++d) {
    EXPECT_GE(intervals[d], 1.0);
    EXPECT_LE(intervals[d], k3D[d]);
  }
  EXPECT_LT(adaptive.bytes(), uniform.bytes());
}

// ---- Domains ------------------------------------------------------------------------------------

ACDF_CHI_SQUARE_TEST(CascadeDomains, ShiftedDomains3D, 1) {
  const auto v = makeFixture(Fixture::Smooth, k3D);
  const std::vector<GridAxis> axes = {GridAxis(16, -3.0f, 5.0f), GridAxis(8, 10.0f, 12.0f), GridAxis(12, -1.0f, -0.5f)};
  const Sampler s = makeCascade(v, axes, withMethods({DM::Adaptive, DM::Uniform, DM::Adaptive}));
  const ChiSquareReport r = runChiSquare(s, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r));
  EXPECT_LE(worstInvertError(s, 10'000, 8), 1e-4);
}

// ---- Wide vertex indices and random configurations -------------------------------------------

ACDF_CHI_SQUARE_TEST(CascadeWide, AxesOver65535CellsUse32BitIndices, 1) {
  // 70000 × 3: level 0 needs 32-bit vertex indices. Chi-square on bins of 100 × 1 cells.
  const std::vector<uint32_t> dims = {70000, 3};
  const auto v = makeFixture(Fixture::ZerosWithIslands, dims);
  const Sampler s = makeCascade(v, unitAxes(dims));
  ChiSquareOptions o;
  o.bins = {700, 3};
  o.subPoints = 1;
  const ChiSquareReport r = runChiSquare(s, o);
  recordReport(r);
  EXPECT_TRUE(Passed(r));
  EXPECT_LE(worstInvertError(s, 20'000, 31), 1e-4);
}

TEST(CascadeRandomConfigurations, ContractHolds) {
  // Random shapes (1..4 axes, some conditioning), fixtures and options: every sample valid,
  // ∫pdf = 1, cell probabilities match pdf() and sum to 1, invert recovers u.
  Pcg32 rng(2026);
  auto pick = [&](uint32_t n) { return rng.nextUint() % n; };
  for (int trial = 0; trial < 60; ++trial) {
    const uint32_t dimsCount = 1 + pick(4);
    std::vector<uint32_t> dims(dimsCount);
    for (uint32_t& d : dims) d = 1 + pick(dimsCount <= 2 ? 40 : 12);
    CascadeOptions o;
    o.conditioningDims = pick(dimsCount);
    for (uint32_t d = o.conditioningDims; d < dimsCount; ++d) o.methods.push_back(pick(3) ? DM::Adaptive : DM::Uniform);
    o.conditional = pick(2) ? ConditionalRule::ExactMass : ConditionalRule::AverageOfNormalized;
    o.simplify.method = pick(2) ? Simplifier::DouglasPeucker : Simplifier::GreedyRefinement;
    o.simplify.metric = pick(2) ? ErrorMetric::Vertical : ErrorMetric::Perpendicular;
    o.simplify.epsilon = std::pow(10.0, -1.0 - 3.0 * rng.nextFloat());
    o.simplify.weightBound = pick(3) == 0 ? 0.0 : 1.0 + 4.0 * rng.nextFloat();
    if (o.simplify.method == Simplifier::GreedyRefinement && pick(2)) o.simplify.maxPoints = 2 + pick(10);
    const Fixture f = kAllFixtures[pick(5)];
    const auto v = makeFixture(f, dims);
    const auto c = std::make_shared<const Cascade>(v, unitAxes(dims), o);
    std::vector<float> condition(o.conditioningDims);
    for (float& x : condition) x = rng.nextFloat();
    const Sampler s = makeCascade(c, condition);
    const std::string what = "trial " + std::to_string(trial) + " " + toString(f) + " dims " +
                             std::to_string(dimsCount) + " conditioning " + std::to_string(o.conditioningDims);
    const ChiSquareReport r = checkSamples(s, 3'000);
    ASSERT_TRUE(r.samplesValid()) << what << ": " << r.summary();
    ASSERT_NEAR(integratePdf(s.axes, s.pdf, 2), 1.0, 1e-4) << what;
    const auto q = s.cellProbabilities();
    ASSERT_NEAR(std::accumulate(q.begin(), q.end(), 0.0), 1.0, 1e-6) << what;
    const auto fromPdf = pdfCellProbabilities(s.axes, s.pdf);
    for (std::size_t i = 0; i < q.size(); ++i)
      ASSERT_NEAR(fromPdf[i], q[i], 2e-6 * q[i] + 1e-30) << what << " cell " << i;
    ASSERT_LE(worstInvertError(s, 500, rng.nextUint()), 1e-4) << what;
  }
}

// ---- Slice grouping ----------------------------------------------------------------------------

CascadeOptions grouped(double tolerance) {
  CascadeOptions o = withMethods({}, 2);
  o.sliceGroupingTolerance = tolerance;
  return o;
}

TEST(CascadeSliceGrouping, OffByDefault) {
  const auto v = makeFixture(Fixture::Smooth, k4D);
  const Cascade c(v, unitAxes(k4D), withMethods({}, 2));
  EXPECT_EQ(c.options().sliceGroupingTolerance, 0.0);
  EXPECT_EQ(c.distinctSlices(), c.slices());
}

TEST(CascadeSliceGrouping, RejectsBadTolerances) {
  const auto v = makeFixture(Fixture::Smooth, k4D);
  for (double bad : {-1e-3, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()})
    EXPECT_THROW((Cascade{v, unitAxes(k4D), grouped(bad)}), std::invalid_argument) << bad;
}

// One validator, for the constructor and the cache reader: it names the option it rejects.
TEST(CascadeOptions, ValidateNamesTheOption) {
  const auto rejected = [](const CascadeOptions& o, std::size_t axes) {
    try {
      validate(o, axes);
    } catch (const OptionError& e) {
      return e.option();
    }
    return std::string("none");
  };
  CascadeOptions o;
  EXPECT_EQ(rejected(o, 1), "none");
  o.conditioningDims = 2;
  EXPECT_EQ(rejected(o, 3), "none");
  EXPECT_EQ(rejected(o, 2), "conditioning_dims");
  o.methods = {DM::Uniform, DM::Adaptive};
  EXPECT_EQ(rejected(o, 3), "methods");
  EXPECT_EQ(rejected(o, 4), "none");
  o.simplify.weightBound = 0.5;
  EXPECT_EQ(rejected(o, 4), "weight_bound");
  o.simplify.weightBound = 0;
  o.sliceGroupingTolerance = -1;
  EXPECT_EQ(rejected(o, 4), "slice_grouping_tolerance");
}

// Fails when grouping counts the compression's own divergence against the tolerance: identical
// slices then stay apart.
TEST(CascadeSliceGrouping, IdenticalSlicesShareOneDistribution) {
  // Reusing an identical slice's distribution adds no divergence at all, so any tolerance > 0
  // groups them (the adaptive compression's own divergence is not "added" by grouping).
  const std::vector<uint32_t> sampled = {k4D[2], k4D[3]};
  const auto one = makeFixture(Fixture::Random, sampled);
  std::vector<float> v;
  for (int s = 0; s < 32; ++s) v.insert(v.end(), one.begin(), one.end());
  const Cascade separate(v, unitAxes(k4D), withMethods({}, 2)), shared(v, unitAxes(k4D), grouped(1e-6));
  EXPECT_EQ(separate.distinctSlices(), 32u);
  EXPECT_EQ(shared.distinctSlices(), 1u);
  EXPECT_LT(shared.bytes() * 10, separate.bytes());
  for (std::size_t slice = 0; slice < 32; ++slice)
    ASSERT_EQ(shared.cellProbabilities(slice), separate.cellProbabilities(0)) << slice;
}

TEST(CascadeSliceGrouping, GroupedSlicesStayWithinTheTolerance) {
  // Smoothly varying slices: some are grouped. Every slice keeps all of its mass reachable, and
  // a slice sampled with another slice's distribution adds at most the tolerance to the
  // χ²-divergence its own distribution has.
  constexpr double kTolerance = 0.02;
  for (Fixture f : {Fixture::Smooth, Fixture::Checkerboard, Fixture::ZerosWithIslands, Fixture::PeakedSun}) {
    SCOPED_TRACE(toString(f));
    const auto v = makeFixture(f, k4D);
    const Cascade separate(v, unitAxes(k4D), withMethods({}, 2)), shared(v, unitAxes(k4D), grouped(kTolerance));
    if (f == Fixture::Smooth) {
      EXPECT_LT(shared.distinctSlices(), shared.slices());
    }
    std::size_t reused = 0;
    for (std::size_t slice = 0; slice < shared.slices(); ++slice) {
      const auto own = sliceValues(v, slice);
      const bool zero = std::all_of(own.begin(), own.end(), [](float x) { return x == 0; });
      const auto q = shared.cellProbabilities(slice);
      EXPECT_EQ(shared.integral(slice), separate.integral(slice));
      if (zero) continue;  // see ZeroSlicesStayUniform
      const CompressionQuality quality = compareCellProbabilities(exactCellProbabilities(own), q);
      EXPECT_EQ(quality.unreachableMass, 0.0) << "slice " << slice;
      const auto ownQ = separate.cellProbabilities(slice);
      if (q != ownQ) {
        ++reused;
        const double ownDivergence = compareCellProbabilities(exactCellProbabilities(own), ownQ).chi2Divergence;
        EXPECT_LE(quality.chi2Divergence, ownDivergence + kTolerance) << "slice " << slice;
      }
    }
    if (f == Fixture::Smooth) {
      EXPECT_GT(reused, 0u);
    }
  }
}

// Fails when an all-zero slice joins the previous group and samples its distribution instead of
// the uniform fallback.
TEST(CascadeSliceGrouping, ZeroSlicesStayUniform) {
  // cascade.h: a slice with no mass samples uniformly and isUniformFallback(slice) reports it;
  // grouping must not hand such a slice another slice's distribution.
  const auto v = makeFixture(Fixture::ZerosWithIslands, k4D);
  const Cascade shared(v, unitAxes(k4D), grouped(0.05));
  std::size_t zeroSlices = 0;
  for (std::size_t slice = 0; slice < shared.slices(); ++slice) {
    if (!shared.isUniformFallback(slice)) continue;
    ++zeroSlices;
    for (double q : shared.cellProbabilities(slice)) ASSERT_NEAR(q, 1.0 / (32 * 16), 1e-9) << "slice " << slice;
  }
  EXPECT_GT(zeroSlices, 0u);
}

ACDF_CHI_SQUARE_TEST(CascadeSliceGrouping, GroupedSliceChiSquare, 1) {
  const auto v = makeFixture(Fixture::Smooth, k4D);
  const auto c = std::make_shared<const Cascade>(v, unitAxes(k4D), grouped(0.02));
  // The last slice of the first row of conditioning cells: grouped with an earlier one.
  const Sampler s = makeCascade(c, {0.05f, 0.9f});
  const ChiSquareReport r = runChiSquare(s, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r));
  EXPECT_LE(worstInvertError(s, 10'000, 12), 1e-4);
}

// ---- Concurrency and determinism ----------------------------------------------------------

struct Draws {
  std::vector<float> x, pdf, pdfAgain, inverted;
  bool operator==(const Draws& o) const {
    auto same = [](const std::vector<float>& a, const std::vector<float>& b) {
      return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
    };
    return same(x, o.x) && same(pdf, o.pdf) && same(pdfAgain, o.pdfAgain) && same(inverted, o.inverted);
  }
};

// Samples i in [0, n) with i % stride == offset, each with its own variates u(i).
void drawInto(const Cascade& c, std::span<const float> condition, std::size_t n, std::size_t offset, std::size_t stride,
              Draws& out) {
  const std::size_t dims = c.sampledDims();
  std::vector<float> u(dims), back(dims);
  for (std::size_t i = offset; i < n; i += stride) {
    Pcg32 rng(i, 77);
    for (float& v : u) v = rng.nextFloat();
    const SampleND s = c.sample(condition, u);
    const std::span<const float> x(s.x.data(), dims);
    c.invert(condition, x, back);
    for (std::size_t d = 0; d < dims; ++d) {
      out.x[i * dims + d] = s.x[d];
      out.inverted[i * dims + d] = back[d];
    }
    out.pdf[i] = s.pdf;
    out.pdfAgain[i] = c.pdf(condition, x);
  }
}

Draws allocate(std::size_t n, std::size_t dims) {
  return {std::vector<float>(n * dims), std::vector<float>(n), std::vector<float>(n), std::vector<float>(n * dims)};
}

TEST(CascadeConcurrency, EightThreadsMatchOneThread) {
  const auto v = makeFixture(Fixture::Random, k4D);
  const Cascade c(v, unitAxes(k4D), withMethods({}, 2));
  const float condition[] = {0.4f, 0.7f};
  constexpr std::size_t kN = 200'000;
  Draws single = allocate(kN, 2), parallel = allocate(kN, 2);
  drawInto(c, condition, kN, 0, 1, single);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < 8; ++t) threads.emplace_back([&, t] { drawInto(c, condition, kN, t, 8, parallel); });
  for (std::thread& t : threads) t.join();
  EXPECT_TRUE(single == parallel);
}

TEST(CascadeConcurrency, BuildDoesNotDependOnTheThreadCount) {
  const auto v = makeFixture(Fixture::Random, std::vector<uint32_t>{8, 4, 64, 32});
  std::unique_ptr<Cascade> serial;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    serial = std::make_unique<Cascade>(v, unitAxes(std::vector<uint32_t>{8, 4, 64, 32}), withMethods({}, 2));
  }
  const Cascade parallel(v, unitAxes(std::vector<uint32_t>{8, 4, 64, 32}), withMethods({}, 2));
  EXPECT_EQ(serial->bytes(), parallel.bytes());
  EXPECT_EQ(serial->pointsPerDimension(), parallel.pointsPerDimension());
  for (std::size_t slice = 0; slice < parallel.slices(); ++slice) {
    ASSERT_EQ(serial->cellProbabilities(slice), parallel.cellProbabilities(slice)) << slice;
    ASSERT_EQ(serial->integral(slice), parallel.integral(slice)) << slice;
  }
  const float condition[] = {0.6f, 0.2f};
  Draws a = allocate(20'000, 2), b = allocate(20'000, 2);
  drawInto(*serial, condition, 20'000, 0, 1, a);
  drawInto(parallel, condition, 20'000, 0, 1, b);
  EXPECT_TRUE(a == b);
}

}  // namespace
