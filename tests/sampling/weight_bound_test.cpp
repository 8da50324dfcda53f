// The weight bound ρ holds for whole cells of a Cascade, not only inside each 1D CDF: no cell of
// the grid gets less than 1/ρ of its exact probability (up to float CDF resolution), so adaptive
// tables cannot add fireflies, whatever the rows merged below an interval look like.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "acdf/fixtures/fixtures.h"
#include "acdf/sampling/cascade.h"
#include "acdf/sampling/quality.h"
#include "acdf/test_support/samplers.h"

namespace acdf {
namespace {

using test_support::Fixture;
using test_support::makeFixture;
using test_support::unitAxes;

std::vector<double> exactProbabilities(std::span<const float> slice) {
  double total = 0;
  for (float v : slice) total += v;
  std::vector<double> p(slice.size());
  for (std::size_t i = 0; i < slice.size(); ++i) p[i] = slice[i] / total;
  return p;
}

// The bound is exact up to the float CDFs' resolution; this slack is far below any real firefly.
constexpr double kRelativeSlack = 0.02;

class WeightBound : public ::testing::TestWithParam<std::tuple<Fixture, double>> {};

TEST_P(WeightBound, HoldsForEveryCellIn2DAnd3D) {
  const auto [fixture, rho] = GetParam();
  for (const std::vector<uint32_t>& dims : {std::vector<uint32_t>{128, 96}, std::vector<uint32_t>{24, 16, 20}}) {
    const auto values = makeFixture(fixture, dims);
    CascadeOptions options;
    options.simplify.weightBound = rho;
    options.simplify.epsilon = 0.01;  // coarse, so rows are merged and the bound has work to do
    const Cascade c(values, unitAxes(dims), options);
    const CompressionQuality q = compareCellProbabilities(exactProbabilities(values), c.cellProbabilities(0));
    EXPECT_LE(q.maxWeightRatio, rho * (1 + kRelativeSlack)) << dims.size() << "D";
    EXPECT_EQ(q.unreachableMass, 0.0);
    EXPECT_LE(q.chi2Divergence, rho - 1.0) << "the divergence is at most ρ − 1 when weights are";
  }
}

INSTANTIATE_TEST_SUITE_P(Fixtures, WeightBound,
                         ::testing::Combine(::testing::Values(Fixture::Smooth, Fixture::PeakedSun,
                                                              Fixture::ZerosWithIslands, Fixture::Checkerboard,
                                                              Fixture::Random),
                                            ::testing::Values(1.5, 4.0)));

TEST(WeightBoundCascade, HoldsPerConditioningSlice) {
  const std::vector<uint32_t> dims{4, 3, 32, 24};
  const auto values = makeFixture(Fixture::Random, dims);
  CascadeOptions options;
  options.conditioningDims = 2;
  options.simplify.epsilon = 0.01;
  const Cascade c(values, unitAxes(dims), options);
  const std::size_t sliceCells = 32 * 24;
  for (std::size_t s = 0; s < c.slices(); ++s) {
    const std::span<const float> slice(values.data() + s * sliceCells, sliceCells);
    const auto q = compareCellProbabilities(exactProbabilities(slice), c.cellProbabilities(s));
    EXPECT_LE(q.maxWeightRatio, options.simplify.weightBound * (1 + kRelativeSlack)) << "slice " << s;
  }
}

TEST(WeightBoundCascade, RowsWithDifferentConditionalsAreNotMerged) {
  // Two kinds of rows with equal totals: light on the left half, or on the right half. The row
  // marginal is flat (a 1D bound alone would merge all rows into one interval and give every
  // cell half its probability... and the empty halves the other half), so only the joint bound
  // keeps the cells' weights at 1.
  const uint32_t rows = 64, cols = 32;
  std::vector<float> values(rows * cols);
  for (uint32_t i = 0; i < rows; ++i)
    for (uint32_t j = 0; j < cols; ++j) values[i * cols + j] = ((i / 8) % 2 == 0) == (j < cols / 2) ? 1.0f : 0.0f;
  CascadeOptions options;
  options.simplify.weightBound = 1.5;
  const Cascade c(values, {GridAxis(rows), GridAxis(cols)}, options);
  const auto q = compareCellProbabilities(exactProbabilities(values), c.cellProbabilities(0));
  EXPECT_LE(q.maxWeightRatio, 1.5 * (1 + kRelativeSlack));
  CascadeOptions unbounded = options;
  unbounded.simplify.weightBound = 0.0;
  const Cascade loose(values, {GridAxis(rows), GridAxis(cols)}, unbounded);
  EXPECT_GE(compareCellProbabilities(exactProbabilities(values), loose.cellProbabilities(0)).maxWeightRatio, 1.9)
      << "without the bound the merged rows halve every lit cell's probability";
}

}  // namespace
}  // namespace acdf
