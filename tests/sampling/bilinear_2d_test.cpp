// Bilinear2D and its 1D kernel (linear_segment.h): the quadratic inversion against a brute-force
// one, at the constant and linear limits and across magnitudes; chi-square against the pdf on
// bins that split every cell (so the shape inside cells is tested, not only cell masses) for
// each fixture and for parameter points on and between grid points; the pdf against the
// definition (the blend of normalised bilinear interpolants, computed here from the raw values);
// exact agreement of sample() and pdf(); ∫pdf = 1; invert; adversarial magnitudes; zero mass;
// validation.

#include "acdf/sampling/bilinear_2d.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <ostream>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "acdf/fixtures/fixtures.h"
#include "acdf/sampling/linear_segment.h"
#include "acdf/sampling/rng.h"
#include "acdf/test_support/chi_square_harness.h"
#include "acdf/test_support/samplers.h"

namespace {

using namespace acdf;
using namespace acdf::test_support;

// Sanitizer builds hunt memory errors, not statistics: a quarter of the samples (still about 160
// expected per bin on the largest histogram).
#ifdef ACDF_SANITIZED_BUILD
constexpr uint64_t kChiSquareSamples = 250'000;
#else
constexpr uint64_t kChiSquareSamples = 1'000'000;
#endif

// Bins split every cell 4 × 4: a wrong root inside a cell (a wrong quadratic, a swapped end
// value, a constant where the density is linear) moves samples between bins of one cell, which
// cell-sized bins would never see.
ChiSquareOptions chi2Options(const Bilinear2D& d) {
  ChiSquareOptions o;
  o.samples = kChiSquareSamples;
  o.bins = {4 * (d.rows() - 1), 4 * (d.columns() - 1)};
  return o;
}

Sampler makeSampler(std::shared_ptr<const Bilinear2D> d, std::vector<float> params = {}) {
  Sampler s;
  s.name = "Bilinear2D";
  s.axes = d->axes();
  s.sample = [d, params](std::span<const float> u) { return d->sample(params, u); };
  s.pdf = [d, params](std::span<const float> x) { return d->pdf(params, x); };
  s.invert = [d, params](std::span<const float> x, std::span<float> u) {
    const std::array<float, 2> v = d->invert(params, x);
    u[0] = v[0];
    u[1] = v[1];
  };
  s.uniformFallback = [d] { return d->uniformFallbackSlices() > 0; };
  s.bytes = [d] { return d->bytes(); };
  s.object = d;
  return s;
}

// ---- The definition, computed independently from the raw values ----------------------------

// A vertex table with its parameter lists, as the constructor takes it.
struct Table {
  std::vector<float> values;
  uint32_t rows = 0, columns = 0;
  std::vector<std::vector<float>> parameters;
  mutable std::vector<double> integrals;  // per slice, filled on first use

  std::shared_ptr<const Bilinear2D> build() const {
    return std::make_shared<const Bilinear2D>(values, rows, columns, parameters);
  }
  std::size_t slices() const {
    std::size_t n = 1;
    for (const auto& p : parameters) n *= p.size();
    return n;
  }
  double value(std::size_t slice, uint32_t r, uint32_t c) const { return values[(slice * rows + r) * columns + c]; }
  // Bilinear interpolation of one slice at x, divided by its integral (uniform without mass).
  double sliceDensity(std::size_t slice, double x0, double x1) const {
    if (integrals.empty()) {
      for (std::size_t k = 0; k < slices(); ++k) {
        double sum = 0;
        for (uint32_t r = 0; r + 1 < rows; ++r)
          for (uint32_t c = 0; c + 1 < columns; ++c)
            sum += 0.25 * (value(k, r, c) + value(k, r + 1, c) + value(k, r, c + 1) + value(k, r + 1, c + 1));
        integrals.push_back(sum / (double(rows - 1) * double(columns - 1)));
      }
    }
    const double integral = integrals[slice];
    if (integral == 0) return 1.0;
    const double g0 = x0 * (rows - 1), g1 = x1 * (columns - 1);
    const uint32_t r = std::min<uint32_t>(uint32_t(g0), rows - 2), c = std::min<uint32_t>(uint32_t(g1), columns - 2);
    const double t0 = g0 - r, t1 = g1 - c;
    const double f = (1 - t0) * ((1 - t1) * value(slice, r, c) + t1 * value(slice, r, c + 1)) +
                     t0 * ((1 - t1) * value(slice, r + 1, c) + t1 * value(slice, r + 1, c + 1));
    return f / integral;
  }
  // pbrt-v4's / Mitsuba's definition: along each parameter the enclosing interval and the
  // clamped weight of its upper end; the density is the weighted sum over the 2^N corners.
  double density(std::span<const float> params, double x0, double x1) const {
    std::vector<std::size_t> first(parameters.size(), 0);
    std::vector<double> alpha(parameters.size(), 0.0);
    for (std::size_t p = 0; p < parameters.size(); ++p) {
      const auto& v = parameters[p];
      if (v.size() == 1) continue;
      std::size_t i = 0;
      while (i + 2 < v.size() && v[i + 1] <= params[p]) ++i;
      first[p] = i;
      alpha[p] = std::clamp((double(params[p]) - v[i]) / (double(v[i + 1]) - v[i]), 0.0, 1.0);
    }
    double sum = 0;
    for (std::size_t corner = 0; corner < (std::size_t{1} << parameters.size()); ++corner) {
      double w = 1;
      std::size_t slice = 0;
      for (std::size_t p = 0; p < parameters.size(); ++p) {
        const bool next = (corner >> p) & 1;
        w *= next ? alpha[p] : 1 - alpha[p];
        std::size_t index = first[p] + (next && parameters[p].size() > 1 ? 1 : 0);
        slice = slice * parameters[p].size() + index;
      }
      if (w > 0) sum += w * sliceDensity(slice, x0, x1);
    }
    return sum;
  }
  // ∫ density dx[1] along the line x[0] = y (exact: the density is piecewise linear along it).
  double line(std::span<const float> params, double y) const {
    double sum = 0;
    for (uint32_t c = 0; c + 1 < columns; ++c)
      sum += 0.5 * (density(params, y, double(c) / (columns - 1)) + density(params, y, double(c + 1) / (columns - 1)));
    return sum / (columns - 1);
  }
  // The probability of x's row strip, and the conditional probability of its column cell on
  // x's line.
  std::array<double, 2> shares(std::span<const float> params, float x0, float x1) const {
    const uint32_t r = std::min<uint32_t>(uint32_t(x0 * (rows - 1)), rows - 2);
    const uint32_t c = std::min<uint32_t>(uint32_t(x1 * (columns - 1)), columns - 2);
    const double strip =
        0.5 * (line(params, double(r) / (rows - 1)) + line(params, double(r + 1) / (rows - 1))) / (rows - 1);
    const double cell =
        0.5 * (density(params, x0, double(c) / (columns - 1)) + density(params, x0, double(c + 1) / (columns - 1))) /
        (columns - 1) / line(params, x0);
    return {strip, cell};
  }
  // How far pdf() may be from density() (the header's precision): 1e-6 relative, plus the float
  // CDFs' absolute error, a few 2^-24, relative to those two probabilities. Exact where the
  // density is 0.
  double tolerance(std::span<const float> params, float x0, float x1) const {
    const double f = density(params, x0, x1);
    if (f == 0) return 0;
    constexpr double kCdfError = 0x1p-22;
    const auto [strip, cell] = shares(params, x0, x1);
    return f * (1e-6 + kCdfError / strip + kCdfError / cell);
  }
};

Table unconditioned(std::vector<float> values, uint32_t rows, uint32_t columns) {
  return Table{std::move(values), rows, columns, {}, {}};
}

// ---- The 1D kernel --------------------------------------------------------------------------

// Brute force: bisection on the textbook CDF (2a t + (b − a) t²) / (a + b) in long double, with
// a and b scaled to max 1.
double bruteForceRoot(double f, double a, double b) {
  const long double m = std::max(a, b);
  const long double A = a / m, B = b / m;
  long double lo = 0, hi = 1;
  for (int i = 0; i < 200; ++i) {
    const long double t = 0.5L * (lo + hi);
    const long double F = (2 * A * t + (B - A) * t * t) / (A + B);
    (F < f ? lo : hi) = t;
  }
  return double(0.5L * (lo + hi));
}

TEST(LinearSegment, ConstantLimitIsTheIdentity) {
  for (double f : {0.0, 1e-300, 1e-9, 0.25, 0.5, 0.9, 1 - 1e-16})
    for (double a : {1e-30, 1.0, 7.5, 1e30}) EXPECT_NEAR(sampleLinearSegment(f, a, a), f, 2e-16 * f) << f << " " << a;
}

TEST(LinearSegment, LinearLimits) {
  for (double f : {1e-12, 0.01, 0.3, 0.5, 0.99, 1 - 1e-12}) {
    EXPECT_NEAR(sampleLinearSegment(f, 0.0, 3.0), std::sqrt(f), 4e-16 * std::sqrt(f)) << f;
    // b = 0: t = 1 − √(1 − f), with full relative precision for small f (no cancellation).
    const double expected = f / (1 + std::sqrt(1 - f));
    EXPECT_NEAR(sampleLinearSegment(f, 3.0, 0.0), expected, 4e-16 * expected) << f;
  }
}

// End values equal to 1e-6 … 1e-15 relative: where the textbook root cancels catastrophically
// and pbrt/Mitsuba switch to the constant formula at 1e-4.
TEST(LinearSegment, NearlyEqualEndValues) {
  for (double gap : {1e-3, 1e-5, 1e-6, 1e-9, 1e-12, 1e-15, -1e-7, -1e-13})
    for (double f : {1e-6, 0.1, 0.5, 0.75, 0.999999}) {
      const double a = 2.0, b = 2.0 * (1 + gap);
      EXPECT_NEAR(sampleLinearSegment(f, a, b), bruteForceRoot(f, a, b), 1e-15) << "gap " << gap << " f " << f;
    }
}

TEST(LinearSegment, MatchesBruteForceAcrossMagnitudes) {
  Pcg32 rng(3);
  double worst = 0;
  for (int i = 0; i < 5000; ++i) {
    // End values from 1e-38 to 1e38 (either may be 0), f anywhere in [0, 1).
    const auto value = [&] { return rng.nextFloat() < 0.1f ? 0.0 : std::pow(10.0, 76.0 * rng.nextDouble() - 38.0); };
    const double a = value(), b = value(), f = rng.nextDouble();
    if (a + b == 0) continue;
    const double t = sampleLinearSegment(f, a, b);
    ASSERT_TRUE(t >= 0 && t <= 1) << t;
    worst = std::max(worst, std::abs(t - bruteForceRoot(f, a, b)));
  }
  std::cout << "worst |t - brute force|: " << worst << "\n";
  EXPECT_LT(worst, 1e-14);
}

TEST(LinearSegment, CdfInvertsTheRootAndIsMonotone) {
  Pcg32 rng(5);
  for (int i = 0; i < 10'000; ++i) {
    const double a = rng.nextDouble() * (i % 3 == 0 ? 0.0 : 1.0), b = rng.nextDouble() * 1e3;
    const double f = rng.nextDouble(), t = sampleLinearSegment(f, a, b);
    ASSERT_NEAR(linearSegmentCdf(t, a, b), f, 1e-14) << a << " " << b << " " << f;
  }
  double previous = 0;
  for (int k = 0; k <= 1000; ++k) {
    const double t = sampleLinearSegment(k / 1000.0, 0.3, 5.0);
    ASSERT_GE(t, previous);
    previous = t;
  }
}

TEST(LinearSegment, DegenerateInputs) {
  EXPECT_EQ(sampleLinearSegment(0.0, 0.0, 1.0), 0.0);  // 0/0 in the formula
  EXPECT_EQ(sampleLinearSegment(0.3, 0.0, 0.0), 0.3);  // no mass: uniform
  EXPECT_EQ(sampleLinearSegment(1.0, 1.0, 0.0), 1.0);
  EXPECT_EQ(sampleLinearSegment(std::nan(""), 1.0, 2.0), 0.0);
  EXPECT_EQ(sampleLinearSegment(2.0, 1.0, 1.0), 1.0);
  EXPECT_EQ(linearSegmentCdf(0.4, 0.0, 0.0), 0.4);
  EXPECT_EQ(linearSegmentCdf(std::nan(""), 1.0, 2.0), 0.0);
  EXPECT_EQ(linearSegmentCdf(1.0, 0.0, 2.0), 1.0);
}

// ---- Unconditioned fixtures ----------------------------------------------------------------

constexpr uint32_t kRows = 9, kColumns = 13;

enum class Case { Smooth, Peaked, ZerosWithIslands, ZeroRows, SingleVertex, CornerVertex, Random };
const Case kCases[] = {Case::Smooth,       Case::Peaked, Case::ZerosWithIslands, Case::ZeroRows, Case::SingleVertex,
                       Case::CornerVertex, Case::Random};

std::string caseName(Case c) {
  switch (c) {
    case Case::Smooth: return "smooth";
    case Case::Peaked: return "peaked";
    case Case::ZerosWithIslands: return "zerosWithIslands";
    case Case::ZeroRows: return "zeroRows";
    case Case::SingleVertex: return "singleVertex";
    case Case::CornerVertex: return "cornerVertex";
    case Case::Random: return "random";
  }
  return "?";
}

// Vertex values on kRows × kColumns: the fixtures of the tree (there for cells, here vertices),
// smooth values with the first, a middle and the last vertex row zero, a single non-zero
// interior vertex (a pyramid: linear densities vanishing at both cell ends), and a single
// non-zero corner vertex (one cell of mass).
Table caseTable(Case c) {
  const std::vector<uint32_t> dims = {kRows, kColumns};
  std::vector<float> v;
  switch (c) {
    case Case::Smooth: v = fixtures::smooth(dims); break;
    case Case::Peaked: v = fixtures::peakedSun(dims); break;
    case Case::ZerosWithIslands: v = fixtures::zerosWithIslands(dims); break;
    case Case::ZeroRows:
      v = fixtures::smooth(dims);
      for (uint32_t r : {0u, 4u, kRows - 1}) std::fill(v.begin() + r * kColumns, v.begin() + (r + 1) * kColumns, 0.0f);
      break;
    case Case::SingleVertex:
      v.assign(kRows * kColumns, 0.0f);
      v[3 * kColumns + 4] = 2.5f;  // its lines x = 0.25 are exact floats: u = 0 lands on a zero line
      break;
    case Case::CornerVertex:
      v.assign(kRows * kColumns, 0.0f);
      v[0] = 1.0f;
      break;
    case Case::Random: v = fixtures::random(dims, 77); break;
  }
  return unconditioned(std::move(v), kRows, kColumns);
}

void PrintTo(Case c, std::ostream* os) { *os << caseName(c); }  // gtest names

class Bilinear2DCaseTest : public ::testing::TestWithParam<Case> {};

ACDF_CHI_SQUARE_TEST_P(Bilinear2DCaseTest, ChiSquare, 1) {
  const auto d = caseTable(GetParam()).build();
  const ChiSquareReport r = runChiSquare(makeSampler(d), chi2Options(*d));
  recordReport(r);
  EXPECT_TRUE(Passed(r));
}

// pdf(sample(u)) equals the returned pdf bit for bit, also at u ∈ {0, 0.5, kOneMinusEpsilon}².
TEST_P(Bilinear2DCaseTest, SamplesMatchPdfExactly) {
  const ChiSquareReport r = checkSamples(makeSampler(caseTable(GetParam()).build()), 100'000, 0.0);
  EXPECT_TRUE(r.samplesValid()) << r.summary();
}

// The midpoint rule with 4 points per cell per axis is exact for a bilinear density.
TEST_P(Bilinear2DCaseTest, PdfIntegratesToOne) {
  const Sampler s = makeSampler(caseTable(GetParam()).build());
  EXPECT_NEAR(integratePdf(s.axes, s.pdf, 4), 1.0, 1e-6);
}

// The pdf is the normalised bilinear interpolant, up to the float CDFs' rounding (Table::tolerance).
TEST_P(Bilinear2DCaseTest, PdfIsTheBilinearInterpolant) {
  const Table t = caseTable(GetParam());
  const auto d = t.build();
  Pcg32 rng(11);
  for (int i = 0; i < 20'000; ++i) {
    const float x[2] = {rng.nextFloat(), rng.nextFloat()};
    ASSERT_NEAR(d->pdf(x), t.density({}, x[0], x[1]), t.tolerance({}, x[0], x[1])) << x[0] << ", " << x[1];
  }
}

// What limits the round trip is the float coordinate: |Δu| ≈ density × half an ulp of x, a few
// 1e-8 here; a wrong CDF or root shows as errors of 1e-3 and more.
TEST_P(Bilinear2DCaseTest, InvertUndoesSample) {
  const double worst = worstInvertError(makeSampler(caseTable(GetParam()).build()), 20'000, 3);
  std::cout << "worst |invert(sample(u)) - u|: " << worst << "\n";
  EXPECT_LT(worst, 2e-6);
}

// No sample where the bilinear density is 0 (on zero rows, outside islands, off the pyramid).
TEST_P(Bilinear2DCaseTest, NeverSamplesZeroDensity) {
  const Table t = caseTable(GetParam());
  const auto d = t.build();
  Pcg32 rng(13);
  for (int i = 0; i < 100'000; ++i) {
    const float u[2] = {i == 0 ? 0.0f : rng.nextFloat(), i == 1 ? kOneMinusEpsilon : rng.nextFloat()};
    const SampleND s = d->sample(u);
    ASSERT_GT(t.density({}, s.x[0], s.x[1]), 0.0) << "u = " << u[0] << ", " << u[1];
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, Bilinear2DCaseTest, ::testing::ValuesIn(kCases),
                         [](const auto& info) { return caseName(info.param); });

// A constant table is the identity map (t = f on every cell): u[0] runs along rows, u[1] along
// columns.
TEST(Bilinear2D, ConstantTableIsTheIdentity) {
  const Bilinear2D d(std::vector<float>(5 * 7, 3.0f), 5, 7);
  Pcg32 rng(17);
  for (int i = 0; i < 10'000; ++i) {
    const float u[2] = {rng.nextFloat(), rng.nextFloat()};
    const SampleND s = d.sample(u);
    ASSERT_NEAR(s.x[0], u[0], 2e-7);
    ASSERT_NEAR(s.x[1], u[1], 2e-7);
    ASSERT_NEAR(s.pdf, 1.0f, 1e-6);
  }
}

TEST(Bilinear2D, RowsComeFromTheFirstVariate) {
  std::vector<float> v(6 * 4, 0.0f);
  std::fill(v.begin(), v.begin() + 3 * 4, 1.0f);  // vertex rows 0–2 of 0–5: mass at x[0] < 0.6 only
  const Bilinear2D d(v, 6, 4);
  Pcg32 rng(19);
  for (int i = 0; i < 10'000; ++i) {
    const float u[2] = {rng.nextFloat(), rng.nextFloat()};
    ASSERT_LT(d.sample(u).x[0], 0.6f);
  }
}

// ---- Parameters ----------------------------------------------------------------------------

// Two parameters with uneven spacing (3 × 4 values), 7 × 11 vertices: each slice a lobe whose
// centre moves with the parameters, on a floor, scaled by a per-slice factor (normalisation must
// remove it); slice (1, 2) has no mass (uniform fallback) and slice (2, 1) a zero vertex row.
Table parameterTable() {
  Table t;
  t.rows = 7;
  t.columns = 11;
  t.parameters = {{0.0f, 0.5f, 2.0f}, {-1.0f, 0.0f, 1.0f, 3.0f}};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 4; ++j)
      for (uint32_t r = 0; r < t.rows; ++r)
        for (uint32_t c = 0; c < t.columns; ++c) {
          const double y = double(r) / (t.rows - 1), x = double(c) / (t.columns - 1);
          const double cy = 0.2 + 0.3 * i, cx = 0.15 + 0.25 * j;
          double v = (std::exp(-((y - cy) * (y - cy) + (x - cx) * (x - cx)) / 0.03) + 0.02 * (i + j)) * (1 + i + 3 * j);
          if (i == 1 && j == 2) v = 0;
          if (i == 2 && j == 1 && r == 3) v = 0;
          t.values.push_back(float(v));
        }
  return t;
}

struct ParameterPoint {
  std::string name;
  std::vector<float> params;
};
const std::vector<ParameterPoint> kParameterPoints = {
    {"onGridPoint", {0.5f, 0.0f}},        // one slice
    {"between", {0.2f, 0.3f}},            // four slices
    {"onLastValue", {2.0f, 2.5f}},        // the last value of parameter 0, between on 1
    {"besideZeroSlice", {0.7f, 1.4f}},    // blends the uniform fallback in
    {"besideZeroRow", {1.9f, -0.1f}},     // blends the slice with a zero row in
    {"outsideTheRange", {-5.0f, 10.0f}},  // clamped to slice (0, 3)
};

void PrintTo(const ParameterPoint& p, std::ostream* os) { *os << p.name; }

class Bilinear2DParameterTest : public ::testing::TestWithParam<ParameterPoint> {};

ACDF_CHI_SQUARE_TEST_P(Bilinear2DParameterTest, ChiSquare, 1) {
  const auto d = parameterTable().build();
  const ChiSquareReport r = runChiSquare(makeSampler(d, GetParam().params), chi2Options(*d));
  recordReport(r);
  EXPECT_TRUE(Passed(r));
}

TEST_P(Bilinear2DParameterTest, SamplesMatchPdfExactly) {
  const ChiSquareReport r = checkSamples(makeSampler(parameterTable().build(), GetParam().params), 100'000, 0.0);
  EXPECT_TRUE(r.samplesValid()) << r.summary();
}

TEST_P(Bilinear2DParameterTest, PdfIntegratesToOne) {
  const Sampler s = makeSampler(parameterTable().build(), GetParam().params);
  EXPECT_NEAR(integratePdf(s.axes, s.pdf, 4), 1.0, 1e-6);
}

// The blend is pbrt's and Mitsuba's: Σ corner weight × that slice's normalised interpolant.
TEST_P(Bilinear2DParameterTest, PdfIsTheBlendOfTheSlices) {
  const Table t = parameterTable();
  const auto d = t.build();
  Pcg32 rng(23);
  for (int i = 0; i < 5000; ++i) {
    const float x[2] = {rng.nextFloat(), rng.nextFloat()};
    const std::vector<float>& p = GetParam().params;
    ASSERT_NEAR(d->pdf(p, x), t.density(p, x[0], x[1]), t.tolerance(p, x[0], x[1])) << x[0] << ", " << x[1];
  }
}

TEST_P(Bilinear2DParameterTest, InvertUndoesSample) {
  const double worst = worstInvertError(makeSampler(parameterTable().build(), GetParam().params), 20'000, 7);
  std::cout << "worst |invert(sample(u)) - u|: " << worst << "\n";
  EXPECT_LT(worst, 2e-6);
}

INSTANTIATE_TEST_SUITE_P(Points, Bilinear2DParameterTest, ::testing::ValuesIn(kParameterPoints),
                         [](const auto& info) { return info.param.name; });

TEST(Bilinear2D, ParameterSlicesAndFallback) {
  const auto d = parameterTable().build();
  EXPECT_EQ(d->parameters(), 2u);
  EXPECT_EQ(d->slices(), 12u);
  EXPECT_EQ(d->uniformFallbackSlices(), 1u);
  EXPECT_TRUE(d->isUniformFallback(1 * 4 + 2));
  // On the zero slice itself: the uniform density.
  const float onZero[] = {0.5f, 1.0f};
  const float x[] = {0.3f, 0.8f};
  EXPECT_NEAR(d->pdf(onZero, x), 1.0, 1e-6);
  EXPECT_TRUE(checkSamples(makeSampler(d, {0.5f, 1.0f}), 10'000, 0.0).samplesValid());
}

// A NaN parameter takes the first value; beyond the ends, the end slices.
TEST(Bilinear2D, ParametersOutsideTheirRange) {
  const auto d = parameterTable().build();
  const float x[] = {0.4f, 0.6f};
  const float first[] = {0.0f, -1.0f}, nan[] = {NAN, NAN}, below[] = {-1.0f, -7.0f};
  EXPECT_EQ(d->pdf(nan, x), d->pdf(first, x));
  EXPECT_EQ(d->pdf(below, x), d->pdf(first, x));
  const float last[] = {2.0f, 3.0f}, above[] = {9.0f, 1e30f};
  EXPECT_EQ(d->pdf(above, x), d->pdf(last, x));
  const float u[] = {0.3f, 0.7f};
  EXPECT_EQ(d->sample(nan, u).x, d->sample(first, u).x);
}

// The RGL isotropic layout: φi has one value, θi several.
ACDF_CHI_SQUARE_TEST(Bilinear2D, OneValueParameter, 1) {
  Table t = parameterTable();
  const std::vector<float> theta = t.parameters[1];
  t.parameters = {{0.0f}, theta};
  t.values.resize(4 * t.rows * t.columns);  // slices (0, ·) of the two-parameter table
  const auto d = t.build();
  EXPECT_EQ(d->slices(), 4u);
  const std::vector<float> p = {123.0f, 0.3f};
  const ChiSquareReport r = runChiSquare(makeSampler(d, p), chi2Options(*d));
  recordReport(r);
  EXPECT_TRUE(Passed(r));
  const float x[] = {0.55f, 0.45f};
  EXPECT_NEAR(d->pdf(p, x), t.density(p, x[0], x[1]), t.tolerance(p, x[0], x[1]));
}

// ---- Adversarial magnitudes ----------------------------------------------------------------

// 1e30 next to 1e-30, denormals next to 1, exact zeros, and two vertex rows of only tiny values
// (denormals, 1e-30: cells 1e-60 of the mass): every sample valid, ∫pdf = 1, pdf > 0 wherever a
// vertex of the cell is positive, and every such cell reachable — variates within a few ulps of
// what invert() gives for a point in the cell sample into it.
ACDF_CHI_SQUARE_TEST(Bilinear2D, AdversarialMagnitudes, 1) {
  constexpr uint32_t rows = 8, columns = 10;
  std::vector<float> v(rows * columns);
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < columns; ++c) {
      float& x = v[r * columns + c];
      x = (r + c) % 2 ? 1e30f : 1e-30f;
      if (r == 2) x = c % 3 == 0 ? std::numeric_limits<float>::denorm_min() : 1e-40f;
      if (r == 3) x = 1e-30f;
      if (r == 5) x = c < 5 ? 0.0f : 1.0f;
      if (r == 6 && c > 6) x = 0.0f;
    }
  const Table t = unconditioned(v, rows, columns);
  const auto d = t.build();
  const Sampler s = makeSampler(d);
  const ChiSquareReport checked = checkSamples(s, 100'000, 0.0);
  EXPECT_TRUE(checked.samplesValid()) << checked.summary();
  EXPECT_NEAR(integratePdf(s.axes, s.pdf, 4), 1.0, 1e-6);
  const ChiSquareReport r = runChiSquare(s, chi2Options(*d));
  recordReport(r);
  EXPECT_TRUE(Passed(r));
  const auto reaches = [&](std::array<float, 2> u, uint32_t row, uint32_t column) {
    for (int step0 = -3; step0 <= 3; ++step0)
      for (int step1 = -3; step1 <= 3; ++step1) {
        float w[2] = {u[0], u[1]};
        for (int k = 0; k < std::abs(step0); ++k) w[0] = std::nextafter(w[0], step0 < 0 ? 0.0f : 1.0f);
        for (int k = 0; k < std::abs(step1); ++k) w[1] = std::nextafter(w[1], step1 < 0 ? 0.0f : 1.0f);
        const SampleND x = d->sample(w);
        if (d->axes()[0].cellOf(x.x[0]) == row && d->axes()[1].cellOf(x.x[1]) == column) return true;
      }
    return false;
  };
  int reachable = 0;
  for (uint32_t r0 = 0; r0 + 1 < rows; ++r0)
    for (uint32_t c0 = 0; c0 + 1 < columns; ++c0) {
      const float corners[] = {v[r0 * columns + c0], v[r0 * columns + c0 + 1], v[(r0 + 1) * columns + c0],
                               v[(r0 + 1) * columns + c0 + 1]};
      if (*std::max_element(std::begin(corners), std::end(corners)) == 0.0f) continue;
      const float x[] = {(r0 + 0.5f) / (rows - 1), (c0 + 0.5f) / (columns - 1)};
      ASSERT_GT(d->pdf(x), 0.0f) << "cell " << r0 << ", " << c0;
      // Strips keep a float step of the marginal CDF however small (strip 2, 1e-60 of the mass),
      // but the conditional on a line mixes two vertex rows' CDFs, and a cell whose share of
      // that mixture is below double resolution has no step in it on any line: cells (5, 6–8),
      // where vertex row 6 is 1e30 or 0 and row 5 is 1 (a share of 1e-30).
      if (t.shares({}, x[0], x[1])[1] > 1e-12) {
        ++reachable;
        EXPECT_TRUE(reaches(d->invert(x), r0, c0)) << "cell " << r0 << ", " << c0;
      }
    }
  EXPECT_EQ(reachable, 7 * 9 - 3);
}

// Tables of only denormals or only huge values normalise to the uniform density.
TEST(Bilinear2D, ExtremeScales) {
  for (float value : {std::numeric_limits<float>::denorm_min(), 1e-40f, std::numeric_limits<float>::max()}) {
    const Bilinear2D d(std::vector<float>(4 * 6, value), 4, 6);
    EXPECT_FALSE(d.isUniformFallback(0));
    const float x[] = {0.3f, 0.6f};
    EXPECT_NEAR(d.pdf(x), 1.0, 1e-6) << value;
  }
}

TEST(Bilinear2D, AllZeroIsUniform) {
  const auto d = std::make_shared<const Bilinear2D>(std::vector<float>(3 * 5, 0.0f), 3, 5);
  EXPECT_TRUE(d->isUniformFallback(0));
  EXPECT_EQ(d->uniformFallbackSlices(), 1u);
  const float x[] = {0.2f, 0.9f};
  EXPECT_NEAR(d->pdf(x), 1.0, 1e-6);
  const Sampler s = makeSampler(d);
  EXPECT_TRUE(checkSamples(s, 10'000, 0.0).samplesValid());
  EXPECT_NEAR(integratePdf(s.axes, s.pdf, 2), 1.0, 1e-6);
}

// The smallest table: one cell.
TEST(Bilinear2D, OneCell) {
  const auto d = std::make_shared<const Bilinear2D>(std::vector<float>{1.0f, 0.0f, 0.0f, 3.0f}, 2, 2);
  const Sampler s = makeSampler(d);
  EXPECT_TRUE(checkSamples(s, 10'000, 0.0).samplesValid());
  const float x[] = {0.25f, 0.75f};
  // f = (0.75·0.25·1 + 0.25·0.75·3 …) bilinear: (1−x0)(1−x1)·1 + x0·x1·3, ∫ = 1/4 + 3/4 = 1.
  EXPECT_NEAR(d->pdf(x), 0.75 * 0.25 + 0.25 * 0.75 * 3, 1e-6);
}

// ---- Interface -----------------------------------------------------------------------------

TEST(Bilinear2D, PdfOutsideTheDomainIsZero) {
  const Bilinear2D d(fixtures::smooth(std::vector<uint32_t>{4, 4}), 4, 4);
  for (auto [a, b] : {std::pair{1.0f, 0.5f}, {0.5f, 1.0f}, {-1e-30f, 0.5f}, {0.5f, NAN}, {INFINITY, 0.1f}}) {
    const float x[] = {a, b};
    EXPECT_EQ(d.pdf(x), 0.0f) << a << ", " << b;
  }
}

TEST(Bilinear2D, Bytes) {
  const auto d = parameterTable().build();
  // Per slice: densities and row CDFs (rows × columns each), row masses and the marginal CDF
  // (rows each); one fallback flag per slice; the 3 + 4 parameter values.
  EXPECT_EQ(d->bytes(), 12 * (2 * 7 * 11 + 2 * 7) * 4 + 12 + 7 * 4);
}

TEST(Bilinear2D, RejectsBadInput) {
  const auto message = [](auto&& build) -> std::string {
    try {
      build();
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "(no exception)";
  };
  const auto contains = [](const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  };
  const std::vector<float> four(4, 1.0f);
  EXPECT_TRUE(contains(message([&] { Bilinear2D(four, 1, 4); }), "at least 2 vertices"))
      << message([&] { Bilinear2D(four, 1, 4); });
  EXPECT_TRUE(contains(message([&] { Bilinear2D(four, 4, 1); }), "at least 2 vertices"));
  EXPECT_TRUE(contains(message([&] { Bilinear2D(four, 2, 3); }), "4 values for 1 slice(s) of 2 × 3"));
  EXPECT_TRUE(contains(message([&] { Bilinear2D(four, 2, 2, {{0.0f, 1.0f}}); }), "8 expected"));

  std::vector<float> v(2 * 2 * 3, 1.0f);
  v[2 * 3 + 4] = -2.0f;  // slice 1, row 1, column 1
  EXPECT_TRUE(contains(message([&] {
                         Bilinear2D(v, 2, 3, {{0.0f, 1.0f}});
                       }),
                       "index 10 (cell [1, 1, 1]) is negative"))
      << message([&] {
           Bilinear2D(v, 2, 3, {{0.0f, 1.0f}});
         });
  v[10] = NAN;
  EXPECT_TRUE(contains(message([&] { Bilinear2D(v, 2, 3, {{0.0f, 1.0f}}); }), "is NaN"));
  v[10] = INFINITY;
  EXPECT_TRUE(contains(message([&] { Bilinear2D(v, 2, 3, {{0.0f, 1.0f}}); }), "infinite"));
  v[10] = 1.0f;

  EXPECT_TRUE(contains(message([&] { Bilinear2D(v, 2, 3, std::vector<std::vector<float>>{std::vector<float>{}}); }),
                       "parameter 0 has no values"));
  EXPECT_TRUE(contains(message([&] { Bilinear2D(v, 2, 3, {{1.0f, 1.0f}}); }), "not strictly increasing at index 1"));
  EXPECT_TRUE(contains(message([&] { Bilinear2D(v, 2, 3, {{2.0f, 1.0f}}); }), "not strictly increasing"));
  EXPECT_TRUE(contains(message([&] { Bilinear2D(v, 2, 3, {{0.0f, NAN}}); }), "parameter 0 value 1 is not finite"));
  EXPECT_TRUE(contains(
      message([&] { Bilinear2D(std::vector<float>(4, 1.0f), 2, 2, std::vector<std::vector<float>>(7, {0.0f})); }),
      "at most 6"));

  const Bilinear2D d(v, 2, 3, {{0.0f, 1.0f}});
  const float u[] = {0.5f, 0.5f}, three[] = {0.1f, 0.2f, 0.3f}, param[] = {0.5f};
  EXPECT_THROW(d.sample(u), std::invalid_argument);  // no parameter value
  EXPECT_THROW(d.sample(param, three), std::invalid_argument);
  EXPECT_THROW(d.pdf(param, three), std::invalid_argument);
  EXPECT_THROW(d.invert(three, u), std::invalid_argument);
  EXPECT_GT(d.sample(param, u).pdf, 0.0f);
}

}  // namespace
