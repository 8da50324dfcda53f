// ThresholdCells: the cell it finds is the number of thresholds at or below v (std::upper_bound)
// whenever v lies in [0, range] and more than the margin from every threshold, and it finds none
// otherwise: on random values, at and a few ulps around every threshold and every threshold ±
// margin, at the ends and outside them, for thresholds spread evenly, unevenly and crowded near
// the ends; and the constructor rejects what it cannot serve.

#include "acdf/sampling/threshold_cells.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <stdexcept>
#include <vector>

namespace {

using acdf::ThresholdCells;

constexpr double kInf = std::numeric_limits<double>::infinity(), kNaN = std::numeric_limits<double>::quiet_NaN();

// The definition: the count of thresholds <= v, when v is a number in [0, range] and no threshold
// lies within the margin of it.
std::optional<uint32_t> expectedCell(const std::vector<double>& thresholds, double range, double margin, double v) {
  if (!(v >= 0.0 && v <= range)) return std::nullopt;
  for (double t : thresholds)
    if (!(v - t > margin) && !(t - v > margin)) return std::nullopt;
  return static_cast<uint32_t>(std::upper_bound(thresholds.begin(), thresholds.end(), v) - thresholds.begin());
}

// Checks cellOf against the definition on random values and around every threshold; returns how
// many answers were cells (so a caller can see both outcomes were exercised).
int checkAgainstUpperBound(const std::vector<double>& thresholds, double range, double margin, std::mt19937_64& rng) {
  const ThresholdCells cells(thresholds, range, margin);
  std::vector<double> values = {-1.0, 2.0 * range, kInf, -kInf, kNaN, margin, range - margin};
  const auto around = [&](double x) {
    double below = x, above = x;
    values.push_back(x);
    for (int i = 0; i < 3; ++i) {
      values.push_back(below = std::nextafter(below, -kInf));
      values.push_back(above = std::nextafter(above, kInf));
    }
  };
  around(0.0);
  around(-0.0);
  around(range);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 20000; ++i) values.push_back(range * unit(rng));
  for (double t : thresholds) {
    around(t);
    around(t - margin);
    around(t + margin);
    values.push_back(t + margin * (2.0 * unit(rng) - 1.0));
  }
  int answered = 0;
  for (double v : values) {
    const std::optional<uint32_t> expected = expectedCell(thresholds, range, margin, v);
    EXPECT_EQ(cells.cellOf(v), expected) << std::hexfloat << "v = " << v << " with " << thresholds.size()
                                         << " thresholds in [0, " << range << "], margin " << margin;
    answered += expected.has_value();
  }
  EXPECT_GT(answered, 10000);
  return answered;
}

std::vector<double> sortedUnique(std::vector<double> t) {
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end()), t.end());
  return t;
}

TEST(ThresholdCells, CellsAreTheCountOfThresholdsAtOrBelow) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (double range : {1.0, 2.0, 4.0, 0.3})
    for (double margin : {1e-9, 1e-4, range * 0x1p-50}) {
      checkAgainstUpperBound({}, range, margin, rng);
      checkAgainstUpperBound({0.5 * range}, range, margin, rng);
      // Evenly spaced, like a lat-long map's pseudo-angles of its pixel edges.
      for (uint32_t cells : {2u, 3u, 7u, 64u, 1000u}) {
        std::vector<double> even;
        for (uint32_t k = 1; k < cells; ++k) even.push_back(range * k / cells);
        checkAgainstUpperBound(even, range, margin, rng);
      }
      // Random, with gaps from the range down to 1e-5 of it, crowded near both ends.
      for (int n : {5, 50, 300}) {
        std::vector<double> t;
        for (int i = 0; i < n; ++i) t.push_back(range * (1e-5 + (1.0 - 2e-5) * std::pow(unit(rng), 3.0)));
        for (int i = 0; i < 5; ++i) t.push_back(range * (1.0 - 1e-4 * (1 + unit(rng))));
        t = sortedUnique(t);
        for (std::size_t k = 1; k < t.size(); ++k)  // keep the bins (half the closest gap) few
          if (t[k] - t[k - 1] < range * 1e-5) t[k] = t[k - 1] + range * 1e-5;
        t.erase(std::remove_if(t.begin(), t.end(), [&](double x) { return !(x < range); }), t.end());
        checkAgainstUpperBound(t, range, margin, rng);
      }
    }
}

TEST(ThresholdCells, EndsNeedNoMargin) {
  const ThresholdCells cells({1.0, 2.0, 3.0}, 4.0, 1e-9);
  EXPECT_EQ(cells.cellOf(0.0), 0u);
  EXPECT_EQ(cells.cellOf(-0.0), 0u);
  EXPECT_EQ(cells.cellOf(1e-300), 0u);
  EXPECT_EQ(cells.cellOf(4.0), 3u);
  EXPECT_EQ(cells.cellOf(std::nextafter(4.0, 0.0)), 3u);
  for (double v : {-1e-300, std::nextafter(4.0, kInf), kNaN, kInf, -kInf}) EXPECT_EQ(cells.cellOf(v), std::nullopt);
  EXPECT_EQ(cells.cellOf(2.0 - 5e-10), std::nullopt);  // within the margin of a threshold
  EXPECT_EQ(cells.cellOf(2.0 + 5e-10), std::nullopt);
  EXPECT_EQ(cells.cellOf(2.0 - 2e-9), 1u);
  EXPECT_EQ(cells.cellOf(2.0 + 2e-9), 2u);
}

TEST(ThresholdCells, RejectsWhatItCannotServe) {
  const auto rejects = [](std::vector<double> thresholds, double range, double margin) {
    EXPECT_THROW(ThresholdCells(std::move(thresholds), range, margin), std::invalid_argument)
        << "range " << range << " margin " << margin;
  };
  rejects({0.5, 0.5}, 1.0, 1e-9);  // not strictly increasing
  rejects({0.6, 0.5}, 1.0, 1e-9);
  rejects({0.2, kNaN, 0.5}, 1.0, 1e-9);
  rejects({0.0, 0.5}, 1.0, 1e-9);  // not inside (0, range)
  rejects({-0.1}, 1.0, 1e-9);
  rejects({0.5, 1.0}, 1.0, 1e-9);
  rejects({0.5, 1.5}, 1.0, 1e-9);
  rejects({0.5, kInf}, 1.0, 1e-9);
  for (double range : {0.0, -1.0, kNaN, kInf}) rejects({}, range, 1e-9);
  for (double margin : {-1e-9, kNaN, kInf, 0.0, 0x1p-51}) rejects({0.5}, 1.0, margin);
  EXPECT_NO_THROW(ThresholdCells({0x1p-1074, 0.5, std::nextafter(1.0, 0.0)}, 1.0, 0x1p-50));
  EXPECT_NO_THROW(ThresholdCells({}, 1.0, 1e-9));
}

}  // namespace
