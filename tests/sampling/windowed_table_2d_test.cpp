// WindowedTable2D: a window's mass is the exact integral of the table's piecewise-constant
// function (against a sum over the coarse cells it overlaps) and adds up over a split window;
// every sample lies strictly inside its window with a positive pdf equal to density / mass, for
// extreme variates too; samples binned over the coarse cells inside a window pass chi-square; the
// coarse grid is much smaller than the fine one and keeps the weight bound on every fine cell;
// bad functions are refused naming the value.

#include "acdf/sampling/windowed_table_2d.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "acdf/sampling/chi_square.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/sample.h"
#include "acdf/test_support/chi_square_registry.h"

namespace {

using namespace acdf;

constexpr uint32_t kColumns = 160, kRows = 120;

// A smooth sky, a hot spot of 2 × 2 fine cells (a sun), and a band of rows and a block of cells
// with nothing in them (the wall below a window; a black patch).
std::vector<float> skyWithSun() {
  std::vector<float> f(kColumns * kRows);
  for (uint32_t j = 0; j < kRows; ++j)
    for (uint32_t i = 0; i < kColumns; ++i) {
      float v = 1.0f + 0.5f * std::sin(0.05f * i) * std::cos(0.03f * j);
      if (j >= 100 && j < 108) v = 0.0f;
      if (i >= 20 && i < 30 && j >= 40 && j < 50) v = 0.0f;
      if ((i == 117 || i == 118) && (j == 31 || j == 32)) v = 40000.0f;
      f[j * kColumns + i] = v;
    }
  return f;
}

const WindowedTable2D& table() {
  static const WindowedTable2D t(skyWithSun(), kColumns, kRows, SimplifyOptions{});
  return t;
}

const WindowedTable2D::Window kWindows[] = {
    {0.0, 1.0, 0.0, 1.0},              // the whole square
    {0.31, 0.87, 0.12, 0.93},          // across the sun, the black block's edge and the empty band
    {0.7301, 0.7402, 0.2601, 0.2702},  // small, inside a few coarse cells around the sun
    {0.5, 0.5000001, 0.4, 0.41},       // a sliver
    {0.13, 0.19, 0.3, 0.45},           // partly over the black block
};

// ∫ of the table's function over the window, cell by cell from the exported arrays.
double massByCells(const WindowedTable2D& t, const WindowedTable2D::Window& w) {
  const auto A = t.columnVertices(), B = t.rowVertices();
  double sum = 0;
  for (uint32_t J = 0; J < t.coarseRows(); ++J)
    for (uint32_t I = 0; I < t.coarseColumns(); ++I) {
      const double da = std::min(A[I + 1], w.a1) - std::max(A[I], w.a0);
      const double db = std::min(B[J + 1], w.b1) - std::max(B[J], w.b0);
      if (da > 0 && db > 0) sum += t.coarseDensity()[J * t.coarseColumns() + I] * da * db;
    }
  return sum;
}

TEST(WindowedTable2D, AWindowsMassIsTheIntegralOfTheTablesFunction) {
  const WindowedTable2D& t = table();
  double fine = 0;
  for (float f : skyWithSun()) fine += f;
  EXPECT_NEAR(t.mass(kWindows[0]), fine / (kColumns * kRows), 1e-12 * fine);
  for (const auto& w : kWindows) {
    const double exact = massByCells(t, w);
    EXPECT_GT(exact, 0.0);
    EXPECT_NEAR(t.mass(w), exact, 1e-9 * exact) << w.a0 << " " << w.b0;
    // Split at an interior point, the four quarters add up to the whole.
    const double a = 0.37 * w.a0 + 0.63 * w.a1, b = 0.71 * w.b0 + 0.29 * w.b1;
    const double quarters = t.mass({w.a0, a, w.b0, b}) + t.mass({a, w.a1, w.b0, b}) + t.mass({w.a0, a, b, w.b1}) +
                            t.mass({a, w.a1, b, w.b1});
    EXPECT_NEAR(quarters, exact, 1e-9 * exact);
  }
  EXPECT_EQ(t.mass({0.2, 0.2, 0.1, 0.5}), 0.0) << "an empty window";
  EXPECT_EQ(t.mass({0.3, 0.6, 101.0 / kRows, 107.0 / kRows}), 0.0) << "inside the empty band";
}

TEST(WindowedTable2D, SamplesLieInTheirWindowWithThePdfOfTheirCell) {
  const WindowedTable2D& t = table();
  const double extremes[] = {0.0, 1e-300, 0.25, 0.5, 1.0 - 0x1p-24, 1.0 - 0x1p-53, 1.0};
  for (const auto& w : kWindows) {
    const double mass = t.mass(w);
    Pcg32 rng(7);
    std::vector<std::pair<double, double>> variates;
    for (double u0 : extremes)
      for (double u1 : extremes) variates.emplace_back(u0, u1);
    for (int k = 0; k < 20000; ++k) variates.emplace_back(rng.nextFloat(), rng.nextFloat());
    for (const auto& [u0, u1] : variates) {
      const WindowedTable2D::Sample s = t.sample(w, mass, u0, u1);
      ASSERT_GT(s.a, w.a0);
      ASSERT_LT(s.a, w.a1);
      ASSERT_GT(s.b, w.b0);
      ASSERT_LT(s.b, w.b1);
      ASSERT_GT(s.pdf, 0.0) << u0 << ", " << u1;
      ASSERT_TRUE(std::isfinite(s.pdf));
      ASSERT_EQ(s.pdf, t.density(s.a, s.b) / mass);
    }
  }
}

// 10⁶ samples in each of three windows, counted in the coarse cells the window overlaps, each
// cell halved both ways (the density is constant inside a coarse cell, so its quarters' shares
// are their areas): expected counts from massByCells.
ACDF_CHI_SQUARE_TEST(WindowedTable2D, SamplesFollowTheDensityInsideTheWindow, 3) {
  const WindowedTable2D& t = table();
  const auto A = t.columnVertices(), B = t.rowVertices();
  for (const auto& w : {kWindows[0], kWindows[1], kWindows[4]}) {
    // The window's own cut of the axes: its ends and the vertices and midpoints inside it.
    auto cuts = [](std::span<const double> vertices, double lo, double hi) {
      std::vector<double> c{lo, hi};
      for (std::size_t k = 0; k + 1 < vertices.size(); ++k)
        for (double x : {vertices[k], 0.5 * (vertices[k] + vertices[k + 1])})
          if (x > lo && x < hi) c.push_back(x);
      std::sort(c.begin(), c.end());
      return c;
    };
    const std::vector<double> ca = cuts(A, w.a0, w.a1), cb = cuts(B, w.b0, w.b1);
    const std::size_t na = ca.size() - 1, nb = cb.size() - 1;
    const double mass = t.mass(w);
    const int n = 1'000'000;
    std::vector<double> observed(na * nb, 0.0), expected(na * nb);
    for (std::size_t j = 0; j < nb; ++j)
      for (std::size_t i = 0; i < na; ++i)
        expected[j * na + i] = n * massByCells(t, {ca[i], ca[i + 1], cb[j], cb[j + 1]}) / mass;
    Pcg32 rng(11);
    for (int k = 0; k < n; ++k) {
      const WindowedTable2D::Sample s = t.sample(w, mass, rng.nextDouble(), rng.nextDouble());
      const std::size_t i = std::upper_bound(ca.begin(), ca.end(), s.a) - ca.begin() - 1;
      const std::size_t j = std::upper_bound(cb.begin(), cb.end(), s.b) - cb.begin() - 1;
      observed[j * na + i] += 1;
    }
    const ChiSquareResult result = chiSquareTest(observed, expected);
    EXPECT_GE(result.pvalue, test_support::chiSquareTestLevel())
        << "chi2 " << result.statistic << " dof " << result.dof << " window " << w.a0 << " " << w.b0;
  }
}

TEST(WindowedTable2D, TheCoarseGridIsSmallAndKeepsTheWeightBound) {
  const WindowedTable2D& t = table();
  EXPECT_LT(t.coarseColumns() * t.coarseRows(), kColumns * kRows / 8)
      << t.coarseColumns() << " x " << t.coarseRows();
  const std::vector<float> f = skyWithSun();
  const double rho = SimplifyOptions{}.weightBound;
  for (uint32_t j = 0; j < kRows; ++j)
    for (uint32_t i = 0; i < kColumns; ++i) {
      const double a = (i + 0.5) / kColumns, b = (j + 0.5) / kRows;
      ASSERT_LE(f[j * kColumns + i], rho * t.density(a, b) * (1 + 1e-6)) << i << ", " << j;
    }
  // Without the bound (ρ = 0) and with a large ε the grid is coarser still.
  SimplifyOptions loose;
  loose.weightBound = 0;
  loose.epsilon = 0.05;
  const WindowedTable2D coarse(f, kColumns, kRows, loose);
  EXPECT_LT(coarse.coarseColumns() * coarse.coarseRows(), t.coarseColumns() * t.coarseRows());
}

TEST(WindowedTable2D, BadFunctionsAreRefusedNamingTheValue) {
  std::vector<float> f(12, 1.0f);
  f[7] = -1.0f;
  try {
    WindowedTable2D(f, 4, 3, SimplifyOptions{});
    FAIL() << "a negative value was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("value 7"), std::string::npos) << e.what();
  }
  f[7] = NAN;
  EXPECT_THROW(WindowedTable2D(f, 4, 3, SimplifyOptions{}), std::invalid_argument);
  EXPECT_THROW(WindowedTable2D(f, 5, 3, SimplifyOptions{}), std::invalid_argument);
  // Nothing at all: every window's mass is 0.
  const WindowedTable2D black(std::vector<float>(12, 0.0f), 4, 3, SimplifyOptions{});
  EXPECT_EQ(black.mass({0, 1, 0, 1}), 0.0);
  // Coordinates out of the square, or NaN (a direction gone bad upstream), find a cell: no index
  // out of range.
  for (double x : {-1.0, 2.0, static_cast<double>(NAN)}) EXPECT_TRUE(std::isfinite(table().density(x, x)));
}

}  // namespace
