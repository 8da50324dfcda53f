// HierarchicalWarp2D: chi-square on every fixture over a power-of-two, an odd and a thin grid and
// a grid with zero rows and columns; exact cell probabilities; invert; the precision of the
// descent on a 2048 × 4096 grid; the identity warp of a constant grid; stratification kept;
// validation. The domain contract (sample() and pdf() agreeing bit for bit, extreme variates
// included; ∫pdf = 1; pdf 0 outside) on the same grids: domain_contract_test.cpp.

#include "acdf/sampling/hierarchical_warp_2d.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "acdf/fixtures/fixtures.h"
#include "acdf/sampling/alias_grid.h"
#include "acdf/sampling/rng.h"
#include "acdf/test_support/chi_square_harness.h"
#include "acdf/test_support/samplers.h"

namespace {

using namespace acdf;
using namespace acdf::test_support;

// rows × columns: a power of two, odd sizes on both axes (levels with missing children), a single
// row, and a tall one-column-wide grid.
const std::vector<std::vector<uint32_t>> kShapes = {{32, 64}, {23, 37}, {1, 50}, {45, 3}};

using Param = std::tuple<std::size_t, Fixture>;  // index into kShapes, fixture

class HierarchicalWarpTest : public ::testing::TestWithParam<Param> {
 protected:
  const std::vector<uint32_t>& dims() const { return kShapes[std::get<0>(GetParam())]; }
  std::vector<float> values() const { return makeFixture(std::get<1>(GetParam()), dims()); }
  Sampler sampler() const { return makeHierarchicalWarp(values(), unitAxes(dims())); }
};

ACDF_CHI_SQUARE_TEST_P(HierarchicalWarpTest, ChiSquare, 1) {
  const ChiSquareReport r = runChiSquare(sampler(), ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r));
}

TEST_P(HierarchicalWarpTest, CellProbabilities) { EXPECT_TRUE(cellProbabilitiesAreExact(sampler(), values())); }

TEST_P(HierarchicalWarpTest, InvertUndoesSample) {
  // Float coordinates hold a cell of 64 with 18 bits to spare: the round trip is good to ~1e-5
  // of u wherever the cell is not tiny, and exact for the corners.
  EXPECT_LT(worstInvertError(sampler(), 20'000, 3), 2e-4);
}

TEST_P(HierarchicalWarpTest, NeverSamplesZeroCells) {
  const Sampler s = sampler();
  const auto v = values();
  Pcg32 rng(5);
  for (int i = 0; i < 100'000; ++i) {
    const float u[2] = {rng.nextFloat(), rng.nextFloat()};
    const SampleND x = s.sample(u);
    ASSERT_GT(v[cellIndex(s.axes, x.point())], 0.0f) << "sample " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(AllFixtures, HierarchicalWarpTest,
                         ::testing::Combine(::testing::Range<std::size_t>(0, kShapes.size()),
                                            ::testing::ValuesIn(kAllFixtures)),
                         [](const auto& info) {
                           const auto& d = kShapes[std::get<0>(info.param)];
                           return std::to_string(d[0]) + "x" + std::to_string(d[1]) + "_" +
                                  toString(std::get<1>(info.param));
                         });

// Rows 0–3, row 17 and the last row, and columns 5 and 6, are zero: whole subtrees of the pyramid
// without mass, next to odd edges.
ACDF_CHI_SQUARE_TEST(HierarchicalWarp, ZeroRowsAndColumns, 1) {
  const std::vector<uint32_t> dims = {41, 30};
  std::vector<float> v = makeFixture(Fixture::Random, dims);
  for (uint32_t r = 0; r < dims[0]; ++r)
    for (uint32_t c = 0; c < dims[1]; ++c)
      if (r < 4 || r == 17 || r == 40 || c == 5 || c == 6) v[r * dims[1] + c] = 0.0f;
  const Sampler s = makeHierarchicalWarp(v, unitAxes(dims));
  const ChiSquareReport r = runChiSquare(s, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r));
  EXPECT_TRUE(checkSamples(s, 100'000, 0.0).samplesValid());
  Pcg32 rng(9);
  for (int i = 0; i < 100'000; ++i) {
    const float u[2] = {rng.nextFloat(), rng.nextFloat()};
    ASSERT_GT(v[cellIndex(s.axes, s.sample(u).point())], 0.0f) << "sample " << i;
  }
}

// On a 2048 × 4096 grid (12 levels) the descent in double loses nothing measurable: invertCell()
// recovers double variates to 1e-9 (the same descent in float arithmetic: 2e-7, i.e. about 1e-3
// of a cell), so the fractions inside the cell are the variates' last bits.
TEST(HierarchicalWarp, DeepDescentKeepsTheVariatesPrecision) {
  const std::vector<uint32_t> dims = {2048, 4096};
  const HierarchicalWarp2D warp(fixtures::peakedSun(dims), unitAxes(dims));
  EXPECT_EQ(warp.levels(), 12u);
  Pcg32 rng(13);
  double worst = 0;
  for (int i = 0; i < 200'000; ++i) {
    const double u0 = rng.nextDouble(), u1 = rng.nextDouble();
    const HierarchicalWarp2D::CellSample s = warp.sampleCell(u0, u1);
    ASSERT_GT(s.probability, 0.0);
    ASSERT_TRUE(s.fractionDown >= 0 && s.fractionDown < 1 && s.fractionRight >= 0 && s.fractionRight < 1);
    const auto back = warp.invertCell(s.row, s.column, s.fractionDown, s.fractionRight);
    worst = std::max({worst, std::abs(back[0] - u0), std::abs(back[1] - u1)});
  }
  EXPECT_LT(worst, 1e-9);
}

// A constant power-of-two grid splits every node in halves, so the warp is the identity.
TEST(HierarchicalWarp, ConstantGridIsTheIdentity) {
  const std::vector<uint32_t> dims = {16, 64};
  const HierarchicalWarp2D warp(std::vector<float>(16 * 64, 2.5f), unitAxes(dims));
  Pcg32 rng(17);
  for (int i = 0; i < 10'000; ++i) {
    const double u0 = rng.nextDouble(), u1 = rng.nextDouble();
    const HierarchicalWarp2D::CellSample s = warp.sampleCell(u0, u1);
    ASSERT_EQ((s.row + s.fractionDown) / 16, u0);
    ASSERT_EQ((s.column + s.fractionRight) / 64, u1);
  }
}

// The point of warping: stratified (jittered n × n) variates stay stratified. The variance of
// the mean of g(x)/pdf(x) over a jittered set is far below that of independent variates (1/90
// here); an alias table, which scatters neighbouring variates over unrelated cells, gains far
// less (1/4 here).
TEST(HierarchicalWarp, StratifiedVariatesStayStratified) {
  const std::vector<uint32_t> dims = {32, 64};
  const auto v = makeFixture(Fixture::Smooth, dims);
  const HierarchicalWarp2D warp(v, unitAxes(dims));
  const AliasGrid alias(v, unitAxes(dims));
  // A smooth integrand unlike the pdf: ∫ g = 1.
  const auto g = [](const SampleND& s) {
    return 1.0 + 0.5 * std::sin(2 * std::numbers::pi * s.x[0]) * std::cos(2 * std::numbers::pi * s.x[1]) +
           (s.x[0] - 0.5);
  };
  constexpr int kStrata = 32, kTrials = 64;
  const auto variance = [&](const auto& sampler, bool stratified) {
    Pcg32 rng(21);
    double sumSquares = 0;
    for (int t = 0; t < kTrials; ++t) {
      double sum = 0;
      for (int i = 0; i < kStrata; ++i)
        for (int j = 0; j < kStrata; ++j) {
          const float a = rng.nextFloat(), b = rng.nextFloat();
          const float u[2] = {stratified ? (i + a) / kStrata : a, stratified ? (j + b) / kStrata : b};
          const SampleND s = sampler.sample(u);
          sum += g(s) / s.pdf;
        }
      const double error = sum / (kStrata * kStrata) - 1.0;
      sumSquares += error * error;
    }
    return sumSquares / kTrials;
  };
  const double warpRatio = variance(warp, true) / variance(warp, false);
  const double aliasRatio = variance(alias, true) / variance(alias, false);
  std::cout << "stratified / independent variance: warp " << warpRatio << ", alias " << aliasRatio << "\n";
  EXPECT_LT(warpRatio, 0.05);
  EXPECT_GT(aliasRatio, 10 * warpRatio);
}

TEST(HierarchicalWarp, AllZeroIsUniform) {
  const std::vector<uint32_t> dims = {5, 7};
  const HierarchicalWarp2D warp(std::vector<float>(35, 0.0f), unitAxes(dims));
  EXPECT_TRUE(warp.isUniformFallback());
  const float x[] = {0.3f, 0.9f};
  EXPECT_NEAR(warp.pdf(x), 1.0, 1e-6);
  const Sampler s = makeHierarchicalWarp(std::vector<float>(35, 0.0f), unitAxes(dims));
  EXPECT_TRUE(checkSamples(s, 10'000, 0.0).samplesValid());
  EXPECT_NEAR(integratePdf(s.axes, s.pdf, 1), 1.0, 1e-6);
}

TEST(HierarchicalWarp, OneCell) {
  const HierarchicalWarp2D warp(std::vector<float>{3.0f}, unitAxes(std::vector<uint32_t>{1, 1}));
  EXPECT_EQ(warp.levels(), 1u);
  const HierarchicalWarp2D::CellSample s = warp.sampleCell(0.25, 0.75);
  EXPECT_EQ(s.probability, 1.0);
  EXPECT_EQ(s.fractionDown, 0.25);
  EXPECT_EQ(s.fractionRight, 0.75);
}

// About 4/3 of a float per cell: the grid, a quarter of it, a sixteenth, … plus odd edges.
TEST(HierarchicalWarp, Bytes) {
  const std::vector<uint32_t> dims = {64, 128};
  const HierarchicalWarp2D warp(makeFixture(Fixture::Smooth, dims), unitAxes(dims));
  EXPECT_EQ(warp.bytes(), 4u * (8192 + 2048 + 512 + 128 + 32 + 8 + 4));
  EXPECT_EQ(warp.levels(), 7u);
}

TEST(HierarchicalWarp, RejectsBadInput) {
  const std::vector<uint32_t> dims = {2, 3};
  std::vector<float> v(6, 1.0f);
  v[4] = -1.0f;
  try {
    HierarchicalWarp2D warp(v, unitAxes(dims));
    FAIL() << "a negative value was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cell [1, 1]"), std::string::npos) << e.what();
  }
  v[4] = NAN;
  EXPECT_THROW(HierarchicalWarp2D(v, unitAxes(dims)), std::invalid_argument);
  v[4] = 1.0f;
  EXPECT_THROW(HierarchicalWarp2D(v, unitAxes(std::vector<uint32_t>{3, 3})), std::invalid_argument);
  EXPECT_THROW(HierarchicalWarp2D(v, unitAxes(std::vector<uint32_t>{6})), std::invalid_argument);
  EXPECT_THROW(HierarchicalWarp2D(v, unitAxes(std::vector<uint32_t>{1, 2, 3})), std::invalid_argument);
  const HierarchicalWarp2D warp(v, unitAxes(dims));
  const float three[] = {0.1f, 0.2f, 0.3f};
  EXPECT_THROW(warp.sample(three), std::invalid_argument);
  EXPECT_EQ(warp.pdf(std::vector<float>{1.0f, 0.5f}), 0.0f);
  EXPECT_EQ(warp.pdf(std::vector<float>{0.5f, NAN}), 0.0f);
}

}  // namespace
