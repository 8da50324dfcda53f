#include "acdf/test_support/samplers.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "acdf/fixtures/fixtures.h"
#include "acdf/sampling/adaptive_cdf_1d.h"
#include "acdf/sampling/alias_grid.h"
#include "acdf/sampling/alias_table_1d.h"
#include "acdf/sampling/hierarchical_warp_2d.h"
#include "acdf/sampling/piecewise_constant_1d.h"
#include "acdf/sampling/rng.h"

namespace acdf::test_support {
namespace {

SampleND toND(Sample1D s) {
  SampleND r;
  r.x[0] = s.x;
  r.pdf = s.pdf;
  return r;
}

template <class T>
Sampler wrap1D(std::shared_ptr<const T> d, std::string name) {
  Sampler s;
  s.name = std::move(name);
  s.axes = {d->axis()};
  s.sample = [d](std::span<const float> u) { return toND(d->sample(u[0])); };
  s.pdf = [d](std::span<const float> x) { return d->pdf(x[0]); };
  if constexpr (requires { d->invert(0.5f); }) {
    s.invert = [d](std::span<const float> x, std::span<float> u) { u[0] = d->invert(x[0]); };
  }
  s.uniformFallback = [d] { return d->isUniformFallback(); };
  s.bytes = [d] { return d->bytes(); };
  s.object = d;
  return s;
}

// The unconditioned N-D classes (AliasGrid, HierarchicalWarp2D): every axis sampled.
template <class T>
Sampler wrapGrid(std::shared_ptr<const T> d, std::string name) {
  Sampler s;
  s.name = std::move(name);
  s.axes = d->axes();
  s.sample = [d](std::span<const float> u) { return d->sample(u); };
  s.pdf = [d](std::span<const float> x) { return d->pdf(x); };
  if constexpr (requires(std::span<const float> x, std::span<float> u) { d->invert(x, u); }) {
    s.invert = [d](std::span<const float> x, std::span<float> u) { d->invert(x, u); };
  }
  s.uniformFallback = [d] { return d->isUniformFallback(); };
  s.cellProbabilities = [d] { return d->cellProbabilities(); };
  s.bytes = [d] { return d->bytes(); };
  s.object = d;
  return s;
}

}  // namespace

std::string toString(Kind1D kind) {
  switch (kind) {
    case Kind1D::PiecewiseConstant: return "PiecewiseConstant1D";
    case Kind1D::Alias: return "AliasTable1D";
    case Kind1D::Adaptive: return "AdaptiveCdf1D";
  }
  return "?";
}

Sampler make1D(Kind1D kind, std::span<const float> values, float lo, float hi, const SimplifyOptions& options) {
  switch (kind) {
    case Kind1D::PiecewiseConstant:
      return wrap1D(std::make_shared<const PiecewiseConstant1D>(values, lo, hi), toString(kind));
    case Kind1D::Alias: return wrap1D(std::make_shared<const AliasTable1D>(values, lo, hi), toString(kind));
    case Kind1D::Adaptive:
      return wrap1D(std::make_shared<const AdaptiveCdf1D>(values, lo, hi, options), toString(kind));
  }
  throw std::logic_error("make1D: unknown kind");
}

Sampler makeAliasGrid(std::span<const float> values, std::vector<GridAxis> axes) {
  return wrapGrid(std::make_shared<const AliasGrid>(values, std::move(axes)), "AliasGrid");
}

Sampler makeCascade(std::shared_ptr<const Cascade> d, std::vector<float> condition) {
  if (condition.size() != d->conditioningDims())
    throw std::invalid_argument("makeCascade: wrong number of condition coordinates");
  Sampler s;
  s.name = "Cascade";
  s.axes.assign(d->axes().begin() + static_cast<std::ptrdiff_t>(d->conditioningDims()), d->axes().end());
  s.sample = [d, condition](std::span<const float> u) { return d->sample(condition, u); };
  s.pdf = [d, condition](std::span<const float> x) { return d->pdf(condition, x); };
  s.invert = [d, condition](std::span<const float> x, std::span<float> u) { d->invert(condition, x, u); };
  const std::size_t slice = d->sliceOf(condition);
  s.uniformFallback = [d, slice] { return d->isUniformFallback(slice); };
  s.cellProbabilities = [d, slice] { return d->cellProbabilities(slice); };
  s.bytes = [d] { return d->bytes(); };
  s.object = d;
  return s;
}

Sampler makeCascade(std::span<const float> values, std::vector<GridAxis> axes, CascadeOptions options) {
  return makeCascade(std::make_shared<const Cascade>(values, std::move(axes), std::move(options)));
}

Sampler makeHierarchicalWarp(std::span<const float> values, std::vector<GridAxis> axes) {
  return wrapGrid(std::make_shared<const HierarchicalWarp2D>(values, std::move(axes)), "HierarchicalWarp2D");
}

std::string toString(Fixture fixture) {
  switch (fixture) {
    case Fixture::Smooth: return "smooth";
    case Fixture::PeakedSun: return "peakedSun";
    case Fixture::ZerosWithIslands: return "zerosWithIslands";
    case Fixture::Checkerboard: return "checkerboard";
    case Fixture::Random: return "random";
  }
  return "?";
}

std::vector<float> makeFixture(Fixture fixture, std::span<const uint32_t> dims) {
  switch (fixture) {
    case Fixture::Smooth: return fixtures::smooth(dims);
    case Fixture::PeakedSun: return fixtures::peakedSun(dims);
    case Fixture::ZerosWithIslands: return fixtures::zerosWithIslands(dims);
    case Fixture::Checkerboard: return fixtures::checkerboard(dims);
    case Fixture::Random: return fixtures::random(dims, 20261121);
  }
  throw std::logic_error("makeFixture: unknown fixture");
}

std::vector<GridAxis> unitAxes(std::span<const uint32_t> dims) {
  std::vector<GridAxis> axes;
  for (uint32_t n : dims) axes.emplace_back(n, 0.0f, 1.0f);
  return axes;
}

double worstInvertError(const Sampler& sampler, uint64_t samples, uint64_t seed) {
  if (!sampler.invert) throw std::invalid_argument(sampler.name + " has no invert()");
  const std::size_t dims = sampler.axes.size();
  std::vector<float> u(dims), back(dims);
  Pcg32 rng(seed);
  double worst = 0.0;
  for (uint64_t i = 0; i < samples; ++i) {
    for (float& x : u) x = rng.nextFloat();
    if (i < 3) std::fill(u.begin(), u.end(), i == 0 ? 0.0f : i == 1 ? kOneMinusEpsilon : 0.5f);
    const SampleND x = sampler.sample(u);
    if (!(x.pdf > 0)) continue;
    sampler.invert(x.point(), back);
    for (std::size_t d = 0; d < dims; ++d) worst = std::max(worst, std::fabs(static_cast<double>(back[d]) - u[d]));
  }
  return worst;
}

ChiSquareReport checkSamples(const Sampler& sampler, uint64_t samples, double pdfTolerance, uint64_t seed) {
  ChiSquareReport report;
  const std::size_t dims = sampler.axes.size();
  std::vector<float> u(dims);
  // Every combination of {0, 0.5, 1-ε} across the axes.
  constexpr float kCorners[] = {0.0f, 0.5f, kOneMinusEpsilon};
  std::size_t combinations = 1;
  for (std::size_t d = 0; d < dims; ++d) combinations *= 3;
  for (std::size_t c = 0; c < combinations; ++c) {
    std::size_t code = c;
    for (std::size_t d = 0; d < dims; ++d, code /= 3) u[d] = kCorners[code % 3];
    checkSample(sampler.axes, u, sampler.sample(u), sampler.pdf, pdfTolerance, report);
  }
  Pcg32 rng(seed);
  for (uint64_t i = 0; i < samples; ++i) {
    for (float& v : u) v = rng.nextFloat();
    checkSample(sampler.axes, u, sampler.sample(u), sampler.pdf, pdfTolerance, report);
  }
  report.samples = samples + combinations;
  report.pdfIntegral = 1.0;  // not measured here
  report.chi2.pvalue = 1.0;
  return report;
}

ChiSquareReport runChiSquare(const Sampler& sampler, const ChiSquareOptions& options) {
  return runChiSquare(sampler.axes, sampler.sample, sampler.pdf, options);
}

::testing::AssertionResult cellProbabilitiesAreExact(const Sampler& sampler, std::span<const float> values) {
  const std::vector<double> q = sampler.cellProbabilities();
  const std::vector<double> exact = exactCellProbabilities(values);
  const std::vector<double> fromPdf = pdfCellProbabilities(sampler.axes, sampler.pdf);
  if (q.size() != exact.size()) {
    return ::testing::AssertionFailure() << q.size() << " cell probabilities for " << exact.size() << " cells";
  }
  double total = 0.0;
  for (double p : q) total += p;
  if (std::fabs(total - 1.0) > 1e-6) return ::testing::AssertionFailure() << "cell probabilities sum to " << total;
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (std::fabs(q[i] - exact[i]) > 1e-6 * exact[i]) {
      return ::testing::AssertionFailure() << "cell " << i << ": " << q[i] << ", exact " << exact[i];
    }
    if (std::fabs(fromPdf[i] - q[i]) > 1e-6 * q[i]) {
      return ::testing::AssertionFailure() << "cell " << i << ": pdf implies " << fromPdf[i] << ", table " << q[i];
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace acdf::test_support
