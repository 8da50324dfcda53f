// Slice grouping (CascadeOptions::sliceGroupingTolerance): conditioning slices whose
// distributions are near-identical share one table, and grouping never leaves mass unreachable.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "acdf/sampling/cascade.h"
#include "acdf/sampling/quality.h"
#include "acdf/sampling/rng.h"
#include "acdf/test_support/chi_square_harness.h"
#include "acdf/test_support/samplers.h"

namespace acdf {
namespace {

using test_support::ChiSquareOptions;
using test_support::makeCascade;
using test_support::runChiSquare;

constexpr uint32_t kCondA = 4, kCondB = 4, kRows = 32, kCols = 16;
constexpr std::size_t kSliceCells = kRows * kCols;

std::vector<GridAxis> axes() { return {GridAxis(kCondA), GridAxis(kCondB), GridAxis(kRows), GridAxis(kCols)}; }

// A peaked function of the sampled cell, the same in every slice up to `shape(slice)`.
template <class Shape>
std::vector<float> slices(Shape shape) {
  std::vector<float> v(kCondA * kCondB * kSliceCells);
  for (std::size_t s = 0; s < kCondA * kCondB; ++s) {
    for (uint32_t r = 0; r < kRows; ++r) {
      for (uint32_t c = 0; c < kCols; ++c) v[s * kSliceCells + r * kCols + c] = shape(s, r, c);
    }
  }
  return v;
}

float peak(double r, double c, double r0, double c0) {
  return static_cast<float>(0.05 + std::exp(-((r - r0) * (r - r0) + (c - c0) * (c - c0)) / 8.0));
}

CascadeOptions grouping(double tolerance) {
  CascadeOptions o;
  o.conditioningDims = 2;
  o.sliceGroupingTolerance = tolerance;
  return o;
}

std::vector<float> conditionOf(std::size_t slice) {
  return {(static_cast<float>(slice / kCondB) + 0.5f) / kCondA, (static_cast<float>(slice % kCondB) + 0.5f) / kCondB};
}

TEST(SliceGrouping, ScaledCopiesShareOneTable) {
  // Every slice is the same function times a slice-dependent scale: one distribution suffices.
  const auto values =
      slices([](std::size_t s, uint32_t r, uint32_t c) { return static_cast<float>(1.0 + s) * peak(r, c, 10, 5); });
  const Cascade separate(values, axes(), grouping(0.0));
  const Cascade grouped(values, axes(), grouping(0.01));
  EXPECT_EQ(separate.distinctSlices(), kCondA * kCondB);
  EXPECT_EQ(grouped.distinctSlices(), 1u);
  EXPECT_LT(grouped.bytes() * 8, separate.bytes());
  Pcg32 rng(3);
  for (std::size_t s = 0; s < grouped.slices(); ++s) {
    EXPECT_DOUBLE_EQ(grouped.integral(s), separate.integral(s)) << "integrals stay per slice";
    const std::vector<float> condition = conditionOf(s);
    ASSERT_EQ(grouped.sliceOf(condition), s);
    for (int i = 0; i < 100; ++i) {
      const float u[2] = {rng.nextFloat(), rng.nextFloat()};
      const SampleND a = grouped.sample(condition, u), b = separate.sample(condition, u);
      // The slices' tables differ only by float rounding of the scaled values.
      EXPECT_NEAR(a.x[0], b.x[0], 1e-5);
      EXPECT_NEAR(a.x[1], b.x[1], 1e-5);
      EXPECT_NEAR(a.pdf, b.pdf, 1e-5 * b.pdf);
    }
  }
}

TEST(SliceGrouping, DifferentSlicesStaySeparate) {
  // The peak moves with the slice: no slice's distribution serves its neighbour.
  const auto values =
      slices([](std::size_t s, uint32_t r, uint32_t c) { return peak(r, c, 2.0 + 1.7 * static_cast<double>(s), 8); });
  const Cascade grouped(values, axes(), grouping(0.01));
  EXPECT_EQ(grouped.distinctSlices(), kCondA * kCondB);
  for (std::size_t s = 0; s < grouped.slices(); ++s) EXPECT_EQ(grouped.distributionOf(s), s);
}

TEST(SliceGrouping, NeverGroupsOverMassTheGroupCannotReach) {
  // Slice 0 is zero on the right half; slice 1 equals it plus a tiny right-half mass. The
  // divergence is tiny, but slice 0's distribution cannot reach that mass: no grouping.
  const auto values = slices([](std::size_t s, uint32_t r, uint32_t c) {
    const float left = c < kCols / 2 ? peak(r, c, 10, 3) : 0.0f;
    return s % 2 == 0 ? left : left + (c >= kCols / 2 ? 1e-6f : 0.0f);
  });
  const Cascade grouped(values, axes(), grouping(1.0));
  // Slice 0 stays alone; slice 1 starts a group whose table reaches everything, so the later
  // slices (with or without the right-half mass) all join it.
  EXPECT_EQ(grouped.distinctSlices(), 2u);
  EXPECT_EQ(grouped.distributionOf(0), 0u);
  for (std::size_t s = 1; s < grouped.slices(); ++s) EXPECT_EQ(grouped.distributionOf(s), 1u) << "slice " << s;
  EXPECT_THROW((void)grouped.distributionOf(grouped.slices()), std::out_of_range);
  const std::vector<float> condition = conditionOf(1);
  const float rightHalf[2] = {0.5f, 0.9f};
  EXPECT_GT(grouped.pdf(condition, rightHalf), 0.0f);
  // Every slice's own cells are reachable by the distribution it uses.
  for (std::size_t s = 0; s < grouped.slices(); ++s) {
    std::vector<double> exact(kSliceCells);
    double total = 0;
    for (std::size_t i = 0; i < kSliceCells; ++i) total += values[s * kSliceCells + i];
    for (std::size_t i = 0; i < kSliceCells; ++i) exact[i] = values[s * kSliceCells + i] / total;
    EXPECT_EQ(compareCellProbabilities(exact, grouped.cellProbabilities(s)).unreachableMass, 0.0) << "slice " << s;
  }
}

ACDF_CHI_SQUARE_TEST(SliceGrouping, GroupedSlicesPassChiSquare, 4) {
  // Slightly different slices grouped under a loose tolerance: each slice still samples exactly
  // the distribution its pdf() reports.
  const auto values =
      slices([](std::size_t s, uint32_t r, uint32_t c) { return peak(r, c, 10.0 + 0.05 * static_cast<double>(s), 5); });
  auto grouped = std::make_shared<const Cascade>(values, axes(), grouping(0.05));
  ASSERT_LT(grouped->distinctSlices(), grouped->slices());
  const ChiSquareOptions options;
  for (std::size_t s : {std::size_t{0}, std::size_t{5}, std::size_t{10}, std::size_t{15}}) {
    const auto sampler = makeCascade(grouped, conditionOf(s));
    const auto report = runChiSquare(sampler.axes, sampler.sample, sampler.pdf, options);
    EXPECT_TRUE(report.passed()) << "slice " << s << ": " << report.summary();
  }
}

TEST(SliceGrouping, RejectsBadTolerance) {
  const auto values = slices([](std::size_t, uint32_t, uint32_t) { return 1.0f; });
  EXPECT_THROW(Cascade(values, axes(), grouping(-1.0)), std::invalid_argument);
  EXPECT_THROW(Cascade(values, axes(), grouping(std::nan(""))), std::invalid_argument);
}

}  // namespace
}  // namespace acdf
