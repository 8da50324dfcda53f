// The numerical contract shared by every distribution: bad input is rejected naming its index,
// zero mass gives a uniform fallback, extreme values (huge dynamic range, denormals, a single
// non-zero cell among 4M) sample correctly, degenerate shapes work, variates outside [0, 1) and
// densities beyond float are clamped, and inconsistent shapes or options are rejected. Variates
// at the ends of [0, 1) and the domain's boundary: domain_contract_test.cpp.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "acdf/fixtures/fixtures.h"
#include "acdf/sampling/adaptive_cdf_1d.h"
#include "acdf/sampling/alias_grid.h"
#include "acdf/sampling/alias_table_1d.h"
#include "acdf/sampling/cascade.h"
#include "acdf/sampling/grid_check.h"
#include "acdf/sampling/piecewise_constant_1d.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/sample.h"
#include "acdf/test_support/chi_square_harness.h"
#include "acdf/test_support/samplers.h"

namespace {

using namespace acdf;
using namespace acdf::test_support;
using DM = DimensionMethod;

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Every distribution class, built from values on a grid of `dims` (1D classes need one axis).
enum class Class { PiecewiseConstant1D, AliasTable1D, AdaptiveCdf1D, AliasGrid, CascadeAdaptive, CascadeUniform };
constexpr Class kAllClasses[] = {Class::PiecewiseConstant1D, Class::AliasTable1D,    Class::AdaptiveCdf1D,
                                 Class::AliasGrid,           Class::CascadeAdaptive, Class::CascadeUniform};
constexpr Class kGridClasses[] = {Class::AliasGrid, Class::CascadeAdaptive, Class::CascadeUniform};

std::string name(Class c) {
  switch (c) {
    case Class::PiecewiseConstant1D: return "PiecewiseConstant1D";
    case Class::AliasTable1D: return "AliasTable1D";
    case Class::AdaptiveCdf1D: return "AdaptiveCdf1D";
    case Class::AliasGrid: return "AliasGrid";
    case Class::CascadeAdaptive: return "CascadeAdaptive";
    case Class::CascadeUniform: return "CascadeUniform";
  }
  return "?";
}

bool is1D(Class c) { return c == Class::PiecewiseConstant1D || c == Class::AliasTable1D || c == Class::AdaptiveCdf1D; }

Sampler build(Class c, std::span<const float> values, std::vector<GridAxis> axes) {
  switch (c) {
    case Class::PiecewiseConstant1D: return make1D(Kind1D::PiecewiseConstant, values, axes[0].lo(), axes[0].hi());
    case Class::AliasTable1D: return make1D(Kind1D::Alias, values, axes[0].lo(), axes[0].hi());
    case Class::AdaptiveCdf1D: return make1D(Kind1D::Adaptive, values, axes[0].lo(), axes[0].hi());
    case Class::AliasGrid: return makeAliasGrid(values, std::move(axes));
    case Class::CascadeAdaptive: return makeCascade(values, std::move(axes));
    case Class::CascadeUniform: {
      CascadeOptions o;
      o.methods.assign(axes.size(), DM::Uniform);
      return makeCascade(values, std::move(axes), o);
    }
  }
  throw std::logic_error("unknown class");
}

// 1D classes on `n` cells of [0,1); grid classes on the given dims.
Sampler build(Class c, std::span<const float> values, std::span<const uint32_t> gridDims) {
  if (is1D(c)) return build(c, values, {GridAxis(uint32_t(values.size()))});
  return build(c, values, unitAxes(gridDims));
}

double volume(std::span<const GridAxis> axes) {
  double v = 1;
  for (const GridAxis& a : axes) v *= double(a.hi()) - double(a.lo());
  return v;
}

// ---- Bad values --------------------------------------------------------------------------------

void expectRejectsNaming(Class c, float bad) {
  const std::vector<uint32_t> dims = {50, 40};
  std::vector<float> values = makeFixture(Fixture::Smooth, dims);
  values[1234] = bad;
  values[1500] = bad;  // a later bad value must not be the one named
  try {
    build(c, values, dims);
    ADD_FAILURE() << name(c) << " accepted " << bad;
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("1234"), std::string::npos) << name(c) << ": " << what;
    EXPECT_EQ(what.find("1500"), std::string::npos) << name(c) << ": " << what;
    if (c == Class::CascadeAdaptive || c == Class::CascadeUniform) {
      // 1234 = 30·40 + 34: the cell is named too ("cell [30, 34]", grid_check.h).
      EXPECT_NE(what.find("[30, 34]"), std::string::npos) << what;
    }
  }
}

TEST(BadValues, NegativeNaNAndInfAreRejectedNamingTheFirstIndex) {
  for (Class c : kAllClasses)
    for (float bad : {-1.0f, -1e-30f, kNaN, kInf, -kInf}) {
      SCOPED_TRACE(name(c) + " value " + std::to_string(bad));
      expectRejectsNaming(c, bad);
    }
}

TEST(BadValues, CheckNonNegativeFiniteNamesIndexAndCell) {
  std::vector<float> v(20, 1.0f);
  v[13] = kNaN;
  const std::vector<GridAxis> axes = {GridAxis(4), GridAxis(5)};
  try {
    checkNonNegativeFinite(v, axes);
    ADD_FAILURE() << "accepted NaN";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("13"), std::string::npos) << what;
    EXPECT_NE(what.find("[2, 3]"), std::string::npos) << what;  // 13 = 2·5 + 3
    EXPECT_NE(what.find("NaN"), std::string::npos) << what;
  }
  v[13] = 0.0f;
  EXPECT_NO_THROW(checkNonNegativeFinite(v, axes));
  EXPECT_NO_THROW(checkNonNegativeFinite(v));
}

TEST(BadValues, EmptyInputIsRejected) {
  const std::vector<float> empty;
  EXPECT_THROW((PiecewiseConstant1D{empty}), std::invalid_argument);
  EXPECT_THROW((AliasTable1D{empty}), std::invalid_argument);
  EXPECT_THROW((AdaptiveCdf1D{empty}), std::invalid_argument);
}

// ---- All zero: uniform fallback ----------------------------------------------------------------

TEST(AllZero, IsAUniformFallback) {
  for (Class c : kAllClasses) {
    SCOPED_TRACE(name(c));
    const std::vector<uint32_t> dims = is1D(c) ? std::vector<uint32_t>{100} : std::vector<uint32_t>{16, 8, 12};
    const std::vector<float> zeros(fixtures::cellCount(dims), 0.0f);
    std::vector<GridAxis> axes;
    if (is1D(c))
      axes = {GridAxis(100, -3.0f, 5.0f)};
    else
      axes = {GridAxis(16, -3.0f, 5.0f), GridAxis(8), GridAxis(12, 0.0f, 2.0f)};
    const Sampler s = build(c, zeros, axes);
    EXPECT_TRUE(s.uniformFallback());
    const double uniform = 1.0 / volume(s.axes);
    const ChiSquareReport r = checkSamples(s, 20'000);
    EXPECT_TRUE(r.samplesValid()) << r.summary();
    Pcg32 rng(2);
    std::vector<float> u(s.axes.size());
    for (int i = 0; i < 1000; ++i) {
      for (float& x : u) x = rng.nextFloat();
      const SampleND x = s.sample(u);
      ASSERT_NEAR(x.pdf, uniform, 1e-5 * uniform);
    }
    EXPECT_NEAR(integratePdf(s.axes, s.pdf, 2), 1.0, 1e-4);
    if (s.cellProbabilities) {
      const auto q = s.cellProbabilities();
      for (double p : q) ASSERT_NEAR(p, 1.0 / double(q.size()), 1e-6 / double(q.size()));
    }
  }
}

ACDF_CHI_SQUARE_TEST(AllZero, UniformFallbackPassesChiSquare, 1) {
  const std::vector<float> zeros(64 * 32, 0.0f);
  const Sampler s = makeCascade(zeros, unitAxes(std::vector<uint32_t>{64, 32}));
  const ChiSquareReport r = runChiSquare(s, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r));
}

TEST(AllZero, NonZeroFunctionIsNotAFallback) {
  for (Class c : kAllClasses) {
    const std::vector<uint32_t> dims = is1D(c) ? std::vector<uint32_t>{100} : std::vector<uint32_t>{10, 10};
    std::vector<float> v(100, 0.0f);
    v[42] = 1e-3f;
    EXPECT_FALSE(build(c, v, dims).uniformFallback()) << name(c);
  }
}

// ---- A single non-zero cell among 4M ---------------------------------------------------------

void expectAllSamplesInCell(const Sampler& s, std::size_t cell, uint64_t samples) {
  const double cellVolume = [&] {
    double v = 1;
    for (const GridAxis& a : s.axes) v *= a.cellWidth();
    return v;
  }();
  const ChiSquareReport r = checkSamples(s, samples);
  EXPECT_TRUE(r.samplesValid()) << r.summary();
  Pcg32 rng(4);
  std::vector<float> u(s.axes.size());
  for (uint64_t i = 0; i < samples; ++i) {
    for (float& x : u) x = rng.nextFloat();
    if (i < 2) std::fill(u.begin(), u.end(), i == 0 ? 0.0f : kOneMinusEpsilon);
    const SampleND x = s.sample(u);
    const std::span<const float> xs(x.x.data(), s.axes.size());
    ASSERT_EQ(cellIndex(s.axes, xs), cell) << s.name << " sample " << i;
    ASSERT_NEAR(x.pdf, 1.0 / cellVolume, 1e-5 / cellVolume) << s.name;
  }
}

TEST(SingleCell, OneNonZeroCellAmong4MIn2D) {
  constexpr uint32_t N = 2048;
  std::vector<float> v(std::size_t(N) * N, 0.0f);
  const std::size_t cell = std::size_t(1234) * N + 777;
  v[cell] = 0.25f;
  const std::vector<uint32_t> dims = {N, N};
  for (Class c : kGridClasses) {
    SCOPED_TRACE(name(c));
    const Sampler s = build(c, v, dims);
    EXPECT_FALSE(s.uniformFallback());
    expectAllSamplesInCell(s, cell, 20'000);
  }
}

TEST(SingleCell, OneNonZeroCellAmong4MIn1D) {
  // 2^22 cells: [0, 1) cannot resolve them in float (GridAxis rejects it), [-1, 1) can.
  constexpr uint32_t N = 1u << 22;
  std::vector<float> v(N, 0.0f);
  const std::size_t cell = 3'000'001;
  v[cell] = 7.0f;
  for (Class c : {Class::PiecewiseConstant1D, Class::AliasTable1D, Class::AdaptiveCdf1D}) {
    SCOPED_TRACE(name(c));
    const Sampler s = build(c, v, {GridAxis(N, -1.0f, 1.0f)});
    expectAllSamplesInCell(s, cell, 20'000);
  }
}

// ---- Extreme magnitudes ------------------------------------------------------------------------

std::vector<float> dynamicRange(std::size_t n) {
  constexpr float kPattern[] = {1e-30f, 1e30f, 1.0f, 1e-20f, 1e20f, 0.0f, 3e29f, 1e-25f, 5e28f, 1e10f, 2e-30f};
  std::vector<float> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = kPattern[(i * 7 + i / 11) % std::size(kPattern)];
  return v;
}

class DynamicRange : public ::testing::TestWithParam<Class> {};

ACDF_CHI_SQUARE_TEST_P(DynamicRange, ChiSquareAndContract, 1) {
  const Class c = GetParam();
  const std::vector<uint32_t> dims = is1D(c) ? std::vector<uint32_t>{1000} : std::vector<uint32_t>{64, 32};
  const auto v = dynamicRange(fixtures::cellCount(dims));
  const Sampler s = build(c, v, dims);
  EXPECT_FALSE(s.uniformFallback());
  const ChiSquareReport r = runChiSquare(s, ChiSquareOptions{});
  recordReport(r);
  EXPECT_TRUE(Passed(r));
  const ChiSquareReport corners = checkSamples(s, 10'000);
  EXPECT_TRUE(corners.samplesValid()) << corners.summary();
}

INSTANTIATE_TEST_SUITE_P(AllClasses, DynamicRange,
                         ::testing::Values(Class::PiecewiseConstant1D, Class::AliasTable1D, Class::AdaptiveCdf1D,
                                           Class::AliasGrid, Class::CascadeAdaptive),
                         [](const auto& info) { return name(info.param); });

// Cell probabilities implied by pdf() against value / Σ values. Tolerance: the float CDF of
// PiecewiseConstant1D and the cascade levels carries ~1 ulp of 1 absolute per stored value, so
// the pdf of a cell of probability p is only exact to ~2.4e-7 / p relative (documented precision).
void expectCellProbabilitiesMatch(const Sampler& s, std::span<const float> values, const std::string& what) {
  const auto exact = exactCellProbabilities(values);
  const auto fromPdf = pdfCellProbabilities(s.axes, s.pdf);
  ASSERT_EQ(exact.size(), fromPdf.size());
  for (std::size_t i = 0; i < exact.size(); ++i)
    ASSERT_NEAR(fromPdf[i], exact[i], 2.5e-7 + 1e-5 * exact[i]) << what << " cell " << i;
}

TEST(Magnitudes, HugeValuesDoNotOverflow) {
  // Up to 3e38 per cell: a float sum overflows, the double sums do not.
  for (Class c : kAllClasses) {
    SCOPED_TRACE(name(c));
    const std::vector<uint32_t> dims = is1D(c) ? std::vector<uint32_t>{1000} : std::vector<uint32_t>{40, 25};
    std::vector<float> v(1000, 3e38f);
    for (std::size_t i = 0; i < v.size(); i += 3) v[i] = 1e38f;
    const Sampler s = build(c, v, dims);
    EXPECT_FALSE(s.uniformFallback());
    const ChiSquareReport r = checkSamples(s, 10'000);
    EXPECT_TRUE(r.samplesValid()) << r.summary();
    EXPECT_NEAR(integratePdf(s.axes, s.pdf, 2), 1.0, 1e-4);
    if (c != Class::AdaptiveCdf1D && c != Class::CascadeAdaptive) expectCellProbabilitiesMatch(s, v, name(c));
  }
}

TEST(Magnitudes, DenormalOnlyInput) {
  for (Class c : kAllClasses) {
    SCOPED_TRACE(name(c));
    const std::vector<uint32_t> dims = is1D(c) ? std::vector<uint32_t>{1000} : std::vector<uint32_t>{40, 25};
    // All equal denormals: a proper (uniform) distribution, not the zero-mass fallback.
    const std::vector<float> same(1000, 1e-42f);
    ASSERT_EQ(std::fpclassify(same[0]), FP_SUBNORMAL);
    const Sampler s = build(c, same, dims);
    EXPECT_FALSE(s.uniformFallback());
    const ChiSquareReport r = checkSamples(s, 10'000);
    EXPECT_TRUE(r.samplesValid()) << r.summary();
    expectCellProbabilitiesMatch(s, same, name(c));

    // Alternating 1e-42 / 3e-42: the pdf keeps their ratio (as the floats represent them).
    std::vector<float> mixed(1000);
    for (std::size_t i = 0; i < mixed.size(); ++i) mixed[i] = i % 2 ? 3e-42f : 1e-42f;
    const Sampler m = build(c, mixed, dims);
    EXPECT_FALSE(m.uniformFallback());
    EXPECT_TRUE(checkSamples(m, 10'000).samplesValid());
    EXPECT_NEAR(integratePdf(m.axes, m.pdf, 2), 1.0, 1e-4);
    if (c != Class::AdaptiveCdf1D && c != Class::CascadeAdaptive) expectCellProbabilitiesMatch(m, mixed, name(c));
  }
}

// ---- Reachability: pdf > 0 wherever f > 0 -----------------------------------------------------

// A cell far below the float CDF's resolution (6e-8 near F = 1) next to huge ones still gets a
// positive pdf from the CDF classes, and a zero cell keeps pdf 0 in the uniform ones: an estimator
// using the table alone must be able to reach all of f's mass. (The alias classes store each cell's probability as
// a float, positive unless it is below 1e-45: not tested at this range.)
TEST(Reachability, EveryCellOfPositiveMassHasPositivePdf) {
  for (Class c : {Class::PiecewiseConstant1D, Class::AdaptiveCdf1D, Class::CascadeAdaptive, Class::CascadeUniform}) {
    SCOPED_TRACE(name(c));
    const std::vector<uint32_t> dims = is1D(c) ? std::vector<uint32_t>{1000} : std::vector<uint32_t>{64, 32};
    const std::vector<float> v = dynamicRange(fixtures::cellCount(dims));
    const Sampler s = build(c, v, dims);
    const std::vector<double> q = pdfCellProbabilities(s.axes, s.pdf);
    std::size_t unreachable = 0, zeroCellsSampled = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (v[i] > 0 && !(q[i] > 0)) ++unreachable;
      if (v[i] == 0 && q[i] != 0) ++zeroCellsSampled;
    }
    EXPECT_EQ(unreachable, 0u) << "cells of positive value with pdf 0";
    // The uniform tables keep a zero cell at pdf 0; an adaptive interval spreads its mass over
    // the zero cells it merged, by design.
    if (c == Class::PiecewiseConstant1D || c == Class::CascadeUniform) {
      EXPECT_EQ(zeroCellsSampled, 0u);
    }
    EXPECT_NEAR(integratePdf(s.axes, s.pdf, 2), 1.0, 1e-4);
    EXPECT_TRUE(checkSamples(s, 10'000).samplesValid());
  }
}

// The same along one CDF as long as a map's row: a bright cell first, then 4095 cells each of
// relative mass 1e-12, far below the CDF's resolution (2^-24) where it runs near 1.
TEST(Reachability, TinyCellsAfterABrightOneKeepAPositiveStep) {
  std::vector<float> v(4096, 1e-12f);
  v[0] = 1.0f;
  v[5] = 0.0f;
  const PiecewiseConstant1D d(v);
  const std::span<const float> cdf = d.cdf();
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (v[k] > 0)
      ASSERT_LT(cdf[k], cdf[k + 1]) << "cell " << k;
    else
      ASSERT_EQ(cdf[k], cdf[k + 1]) << "cell " << k;
  }
  EXPECT_EQ(cdf.back(), 1.0f);
  // The price: each tiny cell took at most about one ulp of F from the bright one.
  const double exact = 1.0 / (1.0 + 4094 * 1e-12);
  EXPECT_LT(cdf[1], exact);
  EXPECT_GT(cdf[1], exact - 4096 * std::ldexp(1.0, -24));
}

// ---- Degenerate shapes -------------------------------------------------------------------------

TEST(Shapes, AxesOfSizeOne) {
  const std::vector<std::vector<uint32_t>> shapes = {{1, 64}, {64, 1}, {1, 1, 1}, {1}, {1, 1}, {3, 1, 5}};
  for (const auto& dims : shapes)
    for (Class c : kAllClasses) {
      if (is1D(c) != (dims.size() == 1)) continue;
      const std::string what = name(c) + " " + std::to_string(dims.size()) + "D " + std::to_string(dims[0]) + "x...";
      SCOPED_TRACE(what);
      const auto v = makeFixture(Fixture::Random, dims);
      const Sampler s = build(c, v, dims);
      const ChiSquareReport r = checkSamples(s, 20'000);
      EXPECT_TRUE(r.samplesValid()) << r.summary();
      EXPECT_NEAR(integratePdf(s.axes, s.pdf, 3), 1.0, 1e-4);
      if (c != Class::CascadeAdaptive && c != Class::AdaptiveCdf1D) {
        const auto exact = exactCellProbabilities(v);
        const auto fromPdf = pdfCellProbabilities(s.axes, s.pdf);
        for (std::size_t i = 0; i < exact.size(); ++i) ASSERT_NEAR(fromPdf[i], exact[i], 3e-7 + 1e-5 * exact[i]);
      }
      if (s.cellProbabilities) {
        const auto q = s.cellProbabilities();
        EXPECT_NEAR(std::accumulate(q.begin(), q.end(), 0.0), 1.0, 1e-6);
      }
      if (s.invert) {
        Pcg32 rng(1);
        std::vector<float> u(s.axes.size()), back(s.axes.size());
        for (int i = 0; i < 2000; ++i) {
          for (float& x : u) x = rng.nextFloat();
          const SampleND x = s.sample(u);
          s.invert(std::span<const float>(x.x.data(), u.size()), back);
          for (std::size_t d = 0; d < u.size(); ++d) ASSERT_NEAR(back[d], u[d], 1e-4) << "axis " << d;
        }
      }
    }
}

TEST(Shapes, EightDimensions) {
  const std::vector<uint32_t> dims(kMaxDims, 2);
  std::vector<float> v(256);
  Pcg32 rng(9);
  for (float& x : v) x = rng.nextFloat() + 0.01f;
  for (Class c : kGridClasses) {
    SCOPED_TRACE(name(c));
    const Sampler s = build(c, v, dims);
    EXPECT_TRUE(checkSamples(s, 5'000).samplesValid());
    EXPECT_NEAR(integratePdf(s.axes, s.pdf, 1), 1.0, 1e-4);
  }
  // Conditioning on 5 of them.
  CascadeOptions o;
  o.conditioningDims = 5;
  const auto c = std::make_shared<const Cascade>(v, unitAxes(dims), o);
  EXPECT_EQ(c->slices(), 32u);
  const Sampler s = makeCascade(c, {0.2f, 0.7f, 0.7f, 0.2f, 0.9f});
  EXPECT_TRUE(checkSamples(s, 5'000).samplesValid());
  EXPECT_NEAR(integratePdf(s.axes, s.pdf, 2), 1.0, 1e-4);
}

// ---- Variates outside [0, 1), clamped densities ------------------------------------------------

TEST(Variates, OutOfRangeVariatesAreClampedLikeClampUnit) {
  // Variates outside [0, 1) (1, 7, −0.5, ±Inf, NaN) behave as clampUnit(u): same sample, inside
  // the domain, never a hang or a NaN.
  const std::vector<uint32_t> grid = {16, 8, 12};
  for (Class c : kAllClasses) {
    SCOPED_TRACE(name(c));
    const std::vector<uint32_t> dims = is1D(c) ? std::vector<uint32_t>{1000} : grid;
    const Sampler s = build(c, makeFixture(Fixture::ZerosWithIslands, dims), dims);
    for (float bad : {1.0f, 7.0f, -0.5f, kInf, -kInf, kNaN}) {
      for (std::size_t d = 0; d < dims.size(); ++d) {
        std::vector<float> u(dims.size(), 0.3f), clamped(dims.size(), 0.3f);
        u[d] = bad;
        clamped[d] = clampUnit(bad);
        const SampleND a = s.sample(u), b = s.sample(clamped);
        for (std::size_t k = 0; k < dims.size(); ++k) {
          ASSERT_EQ(a.x[k], b.x[k]) << "u=" << bad << " on axis " << d;
          ASSERT_TRUE(a.x[k] > s.axes[k].lo() && a.x[k] < s.axes[k].hi());
        }
        ASSERT_EQ(a.pdf, b.pdf);
      }
    }
  }
}

TEST(Variates, ClampHelpers) {
  EXPECT_EQ(clampUnit(0.25f), 0.25f);
  EXPECT_EQ(clampUnit(1.0f), kOneMinusEpsilon);
  EXPECT_EQ(clampUnit(7.0f), kOneMinusEpsilon);
  EXPECT_EQ(clampUnit(-0.5f), 0.0f);
  EXPECT_EQ(clampUnit(kNaN), 0.0f);
  EXPECT_EQ(clampDensity(2.5), 2.5f);
  EXPECT_GT(clampDensity(1e-60), 0.0f);
  EXPECT_EQ(clampDensity(1e60), std::numeric_limits<float>::max());
  EXPECT_EQ(clampDensity(std::numeric_limits<double>::infinity()), std::numeric_limits<float>::max());
}

TEST(Variates, TinyTimesTinyDensityStaysPositive) {
  // 2D with a row and a column of tiny relative mass: the product of per-level densities would
  // underflow float; the returned pdf is clamped positive and matches pdf().
  std::vector<float> v(64 * 64, 1e30f);
  for (int j = 0; j < 64; ++j) v[10 * 64 + j] = 1e-30f;
  v[10 * 64 + 5] = 1e-38f;
  for (Class c : kGridClasses) {
    const Sampler s = build(c, v, std::vector<uint32_t>{64, 64});
    const float x[] = {(10 + 0.5f) / 64, (5 + 0.5f) / 64};
    const float p = s.pdf(x);
    EXPECT_TRUE(std::isfinite(p)) << name(c);
    EXPECT_GE(p, 0.0f) << name(c);
    EXPECT_TRUE(checkSamples(s, 10'000).samplesValid()) << name(c);
  }
}

// ---- Shapes and options that do not fit ------------------------------------------------------

TEST(Rejects, WrongGridShape) {
  const std::vector<float> v(64 * 32, 1.0f);
  const std::vector<GridAxis> axes = {GridAxis(64), GridAxis(32)};
  EXPECT_THROW((Cascade{std::span<const float>(v).first(v.size() - 1), axes}), std::invalid_argument);
  EXPECT_THROW((AliasGrid{std::span<const float>(v).first(v.size() - 1), axes}), std::invalid_argument);
  const std::vector<float> more(64 * 32 + 1, 1.0f);
  EXPECT_THROW((Cascade{more, axes}), std::invalid_argument);
  EXPECT_THROW((AliasGrid{more, axes}), std::invalid_argument);
  EXPECT_THROW((Cascade{v, {}}), std::invalid_argument);
  EXPECT_THROW((AliasGrid{v, {}}), std::invalid_argument);
  const std::vector<GridAxis> nine(kMaxDims + 1, GridAxis(1));
  const std::vector<float> one(1, 1.0f);
  EXPECT_THROW((Cascade{one, nine}), std::invalid_argument);
  EXPECT_THROW((AliasGrid{one, nine}), std::invalid_argument);
  EXPECT_THROW(checkGridShape(5, axes), std::invalid_argument);
  EXPECT_NO_THROW(checkGridShape(64 * 32, axes));
  // Overflowing products of cell counts.
  const std::vector<GridAxis> huge(4, GridAxis(1u << 20));
  // 2^80 cells wrap to 0 in 64 bits: only an overflow check rejects a count of 0.
  EXPECT_THROW(checkGridShape(0, huge), std::invalid_argument);
}

TEST(Rejects, InconsistentCascadeOptions) {
  const std::vector<float> v(64 * 32, 1.0f);
  const std::vector<GridAxis> axes = {GridAxis(64), GridAxis(32)};
  CascadeOptions o;
  o.conditioningDims = 2;  // must leave at least one sampled axis
  EXPECT_THROW((Cascade{v, axes, o}), std::invalid_argument);
  o = {};
  o.methods = {DM::Uniform};  // one entry per sampled dimension
  EXPECT_THROW((Cascade{v, axes, o}), std::invalid_argument);
  o.methods = {DM::Uniform, DM::Uniform, DM::Uniform};
  EXPECT_THROW((Cascade{v, axes, o}), std::invalid_argument);
  o = {};
  o.conditioningDims = 1;
  o.methods = {DM::Uniform, DM::Uniform};
  EXPECT_THROW((Cascade{v, axes, o}), std::invalid_argument);
}

TEST(Rejects, InvalidSimplifyOptions) {
  const std::vector<float> v(64 * 32, 1.0f);
  const std::vector<GridAxis> axes = {GridAxis(64), GridAxis(32)};
  std::vector<SimplifyOptions> bad(5);
  bad[0].epsilon = -1e-3;
  bad[1].weightBound = 0.5;
  bad[2].method = Simplifier::GreedyRefinement;
  bad[2].maxPoints = 1;
  bad[3].maxPoints = 10;  // a budget with Douglas–Peucker
  bad[4].epsilon = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < bad.size(); ++i) {
    EXPECT_THROW((AdaptiveCdf1D{std::span<const float>(v).first(100), 0.0f, 1.0f, bad[i]}), std::invalid_argument) << i;
    CascadeOptions o;
    o.simplify = bad[i];
    EXPECT_THROW((Cascade{v, axes, o}), std::invalid_argument) << i;
    o.methods = {DM::Uniform, DM::Adaptive};
    EXPECT_THROW((Cascade{v, axes, o}), std::invalid_argument) << i;
  }
}

TEST(Rejects, InvalidAxes) {
  EXPECT_THROW((GridAxis{0}), std::invalid_argument);
  EXPECT_THROW((GridAxis{4, 1.0f, 1.0f}), std::invalid_argument);
  EXPECT_THROW((GridAxis{4, 2.0f, 1.0f}), std::invalid_argument);
  EXPECT_THROW((GridAxis{4, kNaN, 1.0f}), std::invalid_argument);
  EXPECT_THROW((GridAxis{4, 0.0f, kInf}), std::invalid_argument);
  EXPECT_THROW((GridAxis{1u << 22, 0.0f, 1.0f}), std::invalid_argument);  // cells below float resolution
  EXPECT_NO_THROW((GridAxis{1u << 20}));
  const std::vector<float> v(10, 1.0f);
  EXPECT_THROW((PiecewiseConstant1D{v, 1.0f, 0.0f}), std::invalid_argument);
  EXPECT_THROW((AliasTable1D{v, 0.0f, kNaN}), std::invalid_argument);
  EXPECT_THROW((AdaptiveCdf1D{v, 3.0f, 3.0f}), std::invalid_argument);
}

}  // namespace
