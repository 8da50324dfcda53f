#pragma once
// Type-erased views of the libsampling distributions, so one test body can run against
// PiecewiseConstant1D, AliasTable1D, AdaptiveCdf1D, AliasGrid, Cascade and HierarchicalWarp2D,
// plus named fixtures.

#include <functional>
#include <memory>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "acdf/sampling/cascade.h"
#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/simplify.h"
#include "acdf/test_support/chi_square_harness.h"

namespace acdf::test_support {

using InvertFn = std::function<void(std::span<const float> x, std::span<float> u)>;

struct Sampler {
  std::string name;
  std::vector<GridAxis> axes;  // the sampled axes; sample() takes axes.size() variates
  SampleFn sample;
  PdfFn pdf;
  InvertFn invert;  // empty when the class has no invert
  std::function<bool()> uniformFallback;
  std::function<std::vector<double>()> cellProbabilities;  // empty for the 1D classes
  std::function<std::size_t()> bytes;
  std::shared_ptr<const void> object;  // keeps the distribution alive
};

enum class Kind1D { PiecewiseConstant, Alias, Adaptive };
std::string toString(Kind1D kind);
inline void PrintTo(Kind1D kind, std::ostream* os) { *os << toString(kind); }  // gtest names

Sampler make1D(Kind1D kind, std::span<const float> values, float lo = 0.0f, float hi = 1.0f,
               const SimplifyOptions& options = {});
Sampler makeAliasGrid(std::span<const float> values, std::vector<GridAxis> axes);
// The distribution of one slice of a Cascade: `condition` holds conditioningDims() coordinates.
Sampler makeCascade(std::shared_ptr<const Cascade> cascade, std::vector<float> condition = {});
Sampler makeCascade(std::span<const float> values, std::vector<GridAxis> axes, CascadeOptions options = {});
Sampler makeHierarchicalWarp(std::span<const float> values, std::vector<GridAxis> axes);

enum class Fixture { Smooth, PeakedSun, ZerosWithIslands, Checkerboard, Random };
inline constexpr Fixture kAllFixtures[] = {Fixture::Smooth, Fixture::PeakedSun, Fixture::ZerosWithIslands,
                                           Fixture::Checkerboard, Fixture::Random};
std::string toString(Fixture fixture);
inline void PrintTo(Fixture fixture, std::ostream* os) { *os << toString(fixture); }
std::vector<float> makeFixture(Fixture fixture, std::span<const uint32_t> dims);

// Axes of `dims` cells each over [0, 1).
std::vector<GridAxis> unitAxes(std::span<const uint32_t> dims);

// invert(sample(u)) against u: draws `samples` variate vectors from Pcg32(seed) (the first three
// all 0, all kOneMinusEpsilon, all 0.5), skips samples of pdf 0 (no unique inverse there) and
// returns the largest |invert(sample(u))[d] − u[d]| over all axes. The sampler must have invert.
double worstInvertError(const Sampler& sampler, uint64_t samples, uint64_t seed);

// Per-sample checks only (no chi-square): x strictly inside the domain, pdf finite > 0, pdf(x)
// matches the returned pdf. Runs `samples` Pcg32 variates plus every corner combination of
// {0, 0.5, kOneMinusEpsilon} across the axes. Fills the sample fields of the report.
ChiSquareReport checkSamples(const Sampler& sampler, uint64_t samples = 100'000, double pdfTolerance = 1e-5,
                             uint64_t seed = 0x9E3779B97F4A7C15ULL);

// Runs the chi-square harness on a Sampler.
ChiSquareReport runChiSquare(const Sampler& sampler, const ChiSquareOptions& options);

// For EXPECT_TRUE: the sampler's cell probabilities (which must sum to 1) and those its pdf
// implies both equal value / Σ values, within a relative 1e-6 (for distributions that keep every
// cell exact: uniform tables, alias grids, hierarchical warps).
::testing::AssertionResult cellProbabilitiesAreExact(const Sampler& sampler, std::span<const float> values);

}  // namespace acdf::test_support
