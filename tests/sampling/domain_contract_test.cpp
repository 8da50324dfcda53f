// The domain contract of every libsampling distribution, one parameterised test over the
// type-erased Sampler (samplers.h): PiecewiseConstant1D, AliasTable1D, AdaptiveCdf1D, AliasGrid,
// Cascade (uniform, adaptive and mixed levels, conditioned slices) and HierarchicalWarp2D, on
// every fixture, on the unit box and on shifted domains. For each:
// - at every combination of u in {0, 0.5, kOneMinusEpsilon} across the axes the sample lies in
//   [innerLo, innerHi] on every axis and is no denormal;
// - for those and 10k to 100k Pcg32 variates: x strictly inside (lo, hi), the returned pdf finite
//   and > 0, and pdf(x) equal to it bit for bit;
// - pdf is 0 outside the half-open domain on each axis (just below lo, at hi and just above it,
//   far outside, ±Inf, NaN), and lo and the largest float below hi are inside it: their pdf is
//   that of the first and last cells;
// - ∫pdf over the domain is 1 within 1e-6.
// The 2D grid samplers (AliasGrid, Cascade, HierarchicalWarp2D) are also chi-square tested on the
// sphere's (φ, θ) rectangle and for uniform positions inside their cells.
// GridAxis::place itself, which every sample goes through, returns exactly what its defining
// formula (the fraction's coordinate, nudged ulp by ulp into the cell range) gives.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "acdf/sampling/cascade.h"
#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/sample.h"
#include "acdf/test_support/chi_square_harness.h"
#include "acdf/test_support/samplers.h"

namespace {

using namespace acdf;
using namespace acdf::test_support;
using DM = DimensionMethod;

struct DomainCase {
  std::string name;
  std::function<Sampler()> make;  // built in the test, not for every instance at start-up
  uint64_t randomSamples;         // Pcg32 variates after the corners
};

// The main shapes on the unit box get 100k random variates. The shifted domains and the 3D
// uniform cascade, whose own risk is at the boundary (checked at every corner and outside), get
// 10k, and each conditioned slice 20k, keeping the program at about 1.2 s of CPU.
constexpr uint64_t kSamples = 100'000, kBoundarySamples = 10'000, kSliceSamples = 20'000;

void PrintTo(const DomainCase& c, std::ostream* os) { *os << c.name; }

constexpr float kInf = std::numeric_limits<float>::infinity();

std::vector<GridAxis> axesOver(const std::vector<uint32_t>& dims, bool shifted) {
  if (!shifted) return unitAxes(dims);
  // Different widths and offsets per axis, away from 0 and crossing it.
  constexpr float kBounds[][2] = {{-3.0f, 5.0f}, {10.0f, 12.0f}, {-1.0f, -0.5f}};
  std::vector<GridAxis> axes;
  for (std::size_t d = 0; d < dims.size(); ++d) axes.emplace_back(dims[d], kBounds[d][0], kBounds[d][1]);
  return axes;
}

std::string domainName(bool shifted) { return shifted ? "shifted" : "unit"; }

std::vector<DomainCase> domainCases() {
  std::vector<DomainCase> cases;
  for (Fixture f : kAllFixtures) {
    const std::string fixture = toString(f);
    for (bool shifted : {false, true}) {
      for (Kind1D kind : {Kind1D::PiecewiseConstant, Kind1D::Alias, Kind1D::Adaptive})
        cases.push_back({toString(kind) + "_" + domainName(shifted) + "_" + fixture,
                         [=] {
                           const std::vector<uint32_t> dims = {1000};
                           const GridAxis axis = axesOver(dims, shifted)[0];
                           return make1D(kind, makeFixture(f, dims), axis.lo(), axis.hi());
                         },
                         shifted ? kBoundarySamples : kSamples});
    }

    const std::vector<uint32_t> k2D = {64, 32}, k3D = {16, 8, 12};
    for (const auto& [shape, dims, shiftedToo] : {std::tuple{"2D", k2D, false}, std::tuple{"3D", k3D, true}})
      for (bool shifted : {false, true}) {
        if (shifted && !shiftedToo) continue;
        cases.push_back({std::string("AliasGrid_") + shape + "_" + domainName(shifted) + "_" + fixture,
                         [=] { return makeAliasGrid(makeFixture(f, dims), axesOver(dims, shifted)); },
                         shifted ? kBoundarySamples : kSamples});
      }

    struct CascadeShape {
      std::string name;
      std::vector<uint32_t> dims;
      std::vector<DM> methods;  // empty: all adaptive (the default)
      bool shiftedToo;
      uint64_t samples;  // on the unit box
    };
    const CascadeShape cascadeShapes[] = {
        {"2D_Uniform", k2D, {DM::Uniform, DM::Uniform}, false, kSamples},
        {"2D_Adaptive", k2D, {}, false, kSamples},
        {"3D_Uniform", k3D, {DM::Uniform, DM::Uniform, DM::Uniform}, true, kBoundarySamples},
        {"3D_Adaptive", k3D, {}, true, kSamples},
        {"3D_MixedAUA", k3D, {DM::Adaptive, DM::Uniform, DM::Adaptive}, false, kSamples},
    };
    for (const CascadeShape& shape : cascadeShapes)
      for (bool shifted : {false, true}) {
        if (shifted && !shape.shiftedToo) continue;
        cases.push_back({"Cascade_" + shape.name + "_" + domainName(shifted) + "_" + fixture,
                         [=] {
                           CascadeOptions o;
                           o.methods = shape.methods;
                           return makeCascade(makeFixture(f, shape.dims), axesOver(shape.dims, shifted), o);
                         },
                         shifted ? kBoundarySamples : shape.samples});
      }
    // 8 × 4 conditioning cells × 32 × 16 sampled: cell (1, 0), inside the islands of
    // zerosWithIslands, and cell (7, 2), where it is all zero (the uniform fallback).
    const std::vector<std::vector<float>> conditions = {{0.13f, 0.1f}, {0.93f, 0.6f}};
    for (std::size_t slice = 0; slice < conditions.size(); ++slice)
      cases.push_back({"CascadeSlice_4D_slice" + std::to_string(slice) + "_" + fixture,
                       [=] {
                         const std::vector<uint32_t> dims = {8, 4, 32, 16};
                         CascadeOptions o;
                         o.conditioningDims = 2;
                         return makeCascade(std::make_shared<const Cascade>(makeFixture(f, dims), unitAxes(dims), o),
                                            conditions[slice]);
                       },
                       kSliceSamples});

    // A power of two, odd sizes on both axes, a single row and a one-column-wide grid.
    const std::vector<std::vector<uint32_t>> warpShapes = {{32, 64}, {23, 37}, {1, 50}, {45, 3}};
    for (const std::vector<uint32_t>& dims : warpShapes)
      for (bool shifted : {false, true}) {
        if (shifted && dims != warpShapes[1]) continue;
        cases.push_back({"HierarchicalWarp2D_" + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "_" +
                             domainName(shifted) + "_" + fixture,
                         [=] { return makeHierarchicalWarp(makeFixture(f, dims), axesOver(dims, shifted)); },
                         shifted ? kBoundarySamples : kSamples});
      }
  }
  return cases;
}

class DomainContract : public ::testing::TestWithParam<DomainCase> {};

// Every combination of {0, 0.5, kOneMinusEpsilon} across the axes: samples in [innerLo, innerHi],
// which at u = 0 on [0, 1) is a normal float, not a denormal next to lo.
void expectCornersInsideTheInnerDomain(const Sampler& s) {
  constexpr float kCorners[] = {0.0f, 0.5f, kOneMinusEpsilon};
  const std::size_t dims = s.axes.size();
  std::size_t combinations = 1;
  for (std::size_t d = 0; d < dims; ++d) combinations *= 3;
  std::vector<float> u(dims);
  for (std::size_t c = 0; c < combinations; ++c) {
    std::size_t code = c;
    for (std::size_t d = 0; d < dims; ++d, code /= 3) u[d] = kCorners[code % 3];
    const SampleND x = s.sample(u);
    for (std::size_t d = 0; d < dims; ++d) {
      EXPECT_GE(x.x[d], s.axes[d].innerLo()) << "axis " << d << " u[0] " << u[0];
      EXPECT_LE(x.x[d], s.axes[d].innerHi()) << "axis " << d << " u[0] " << u[0];
      EXPECT_NE(std::fpclassify(x.x[d]), FP_SUBNORMAL) << "axis " << d << " x " << x.x[d];
    }
  }
}

// From the centre of the first (last) cell on every axis, on each axis in turn: points outside
// have pdf 0; lo (the largest float below hi) has the first (last) cell's pdf, and so do the
// corners with every axis there.
void expectPdfZeroOutsideTheHalfOpenDomain(const Sampler& s) {
  const std::size_t dims = s.axes.size();
  std::vector<float> first(dims), last(dims);
  for (std::size_t d = 0; d < dims; ++d) {
    const GridAxis& a = s.axes[d];
    first[d] = a.place(0, 1, 0.5);
    last[d] = a.place(a.cells() - 1, a.cells(), 0.5);
  }
  const float firstPdf = s.pdf(first), lastPdf = s.pdf(last);
  std::vector<float> loCorner(dims), hiCorner(dims);
  for (std::size_t d = 0; d < dims; ++d) {
    loCorner[d] = s.axes[d].lo();
    hiCorner[d] = std::nextafter(s.axes[d].hi(), s.axes[d].lo());
  }
  EXPECT_EQ(s.pdf(loCorner), firstPdf) << "at lo on every axis";
  EXPECT_EQ(s.pdf(hiCorner), lastPdf) << "just below hi on every axis";
  for (std::size_t d = 0; d < dims; ++d) {
    const float lo = s.axes[d].lo(), hi = s.axes[d].hi(), width = hi - lo;
    std::vector<float> x = first;
    x[d] = lo;
    EXPECT_EQ(s.pdf(x), firstPdf) << "axis " << d << " at lo";
    x = last;
    x[d] = std::nextafter(hi, lo);
    EXPECT_EQ(s.pdf(x), lastPdf) << "axis " << d << " just below hi";
    for (float bad : {std::nextafter(lo, -kInf), lo - width, hi, std::nextafter(hi, kInf), hi + width, 1e30f, -1e30f,
                      kInf, -kInf, std::numeric_limits<float>::quiet_NaN()}) {
      x = first;
      x[d] = bad;
      EXPECT_EQ(s.pdf(x), 0.0f) << "axis " << d << " x " << bad;
    }
  }
}

TEST_P(DomainContract, Holds) {
  const DomainCase& c = GetParam();
  const Sampler s = c.make();
  expectCornersInsideTheInnerDomain(s);
  const ChiSquareReport samples = checkSamples(s, c.randomSamples, 0.0);
  EXPECT_TRUE(samples.samplesValid()) << samples.summary();
  expectPdfZeroOutsideTheHalfOpenDomain(s);
  // Exact for pdfs constant on cells but for the float densities' rounding (at most 5e-8 here).
  EXPECT_NEAR(integratePdf(s.axes, s.pdf, 2), 1.0, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(AllSamplers, DomainContract, ::testing::ValuesIn(domainCases()),
                         [](const auto& info) { return info.param.name; });

// The 2D grid samplers on domains other than the unit box, by chi-square: the same tests for
// every class, since each maps its cell and in-cell fractions onto the axes the same way.
struct GridSamplerCase {
  std::string name;
  std::function<Sampler(std::span<const float> values, std::vector<GridAxis> axes)> make;
};

void PrintTo(const GridSamplerCase& c, std::ostream* os) { *os << c.name; }

class GridSamplerDomains : public ::testing::TestWithParam<GridSamplerCase> {};

// The sphere's (φ, θ) rectangle: samples follow the function on it, and a constant function has
// the density 1/(2π·π) there.
ACDF_CHI_SQUARE_TEST_P(GridSamplerDomains, SphericalDomain, 2) {
  constexpr float kTwoPi = 2 * std::numbers::pi_v<float>, kPi = std::numbers::pi_v<float>;
  const std::vector<uint32_t> dims = {64, 32};
  const std::vector<GridAxis> axes = {GridAxis(64, 0.0f, kTwoPi), GridAxis(32, 0.0f, kPi)};
  for (Fixture f : {Fixture::Random, Fixture::PeakedSun}) {
    const ChiSquareReport r = runChiSquare(GetParam().make(makeFixture(f, dims), axes), ChiSquareOptions{});
    recordReport(r);
    EXPECT_TRUE(Passed(r)) << toString(f);
  }
  const Sampler flat = GetParam().make(std::vector<float>(64 * 32, 1.0f), axes);
  const float x[] = {1.0f, 2.0f};
  EXPECT_NEAR(flat.pdf(x), 1.0 / (2 * std::numbers::pi * std::numbers::pi), 1e-7);
}

// Bins halving every cell on both axes (of odd and even counts): where a sample lands inside its
// cell comes from the variates' remainders, and must be uniform there.
ACDF_CHI_SQUARE_TEST_P(GridSamplerDomains, PositionsAreUniformWithinCells, 1) {
  const std::vector<uint32_t> dims = {17, 32};
  const Sampler s = GetParam().make(makeFixture(Fixture::Random, dims), unitAxes(dims));
  ChiSquareOptions o;
  o.bins = {34, 64};
  const ChiSquareReport r = runChiSquare(s, o);
  recordReport(r);
  EXPECT_TRUE(Passed(r));
}

INSTANTIATE_TEST_SUITE_P(
    AllGridSamplers, GridSamplerDomains,
    ::testing::Values(
        GridSamplerCase{"AliasGrid", [](std::span<const float> v, std::vector<GridAxis> a) {
                          return makeAliasGrid(v, std::move(a));
                        }},
        GridSamplerCase{"Cascade", [](std::span<const float> v, std::vector<GridAxis> a) {
                          return makeCascade(v, std::move(a));
                        }},
        GridSamplerCase{"HierarchicalWarp2D",
                        [](std::span<const float> v, std::vector<GridAxis> a) {
                          return makeHierarchicalWarp(v, std::move(a));
                        }}),
    [](const auto& info) { return info.param.name; });

// What place() is defined to return: the coordinate at fraction t of the cell range, clamped to
// the inner domain, then moved ulp by ulp until its cell is in [first, end).
float nudgedFormula(const GridAxis& a, uint32_t first, uint32_t end, double t) {
  const double g = first + std::clamp(t, 0.0, 1.0) * (end - first);
  float x = std::clamp(static_cast<float>(a.lo() + g * a.cellWidth()), a.innerLo(), a.innerHi());
  while (a.cellOf(x) < first) x = std::nextafter(x, a.hi());
  while (a.cellOf(x) >= end) x = std::nextafter(x, a.lo());
  return x;
}

TEST(GridAxisPlace, IsTheNudgedFormulaBitForBit) {
  // Unit and angle domains, an offset one, a huge grid, and cells of 4 and 3 ulps of their
  // coordinates' magnitude, where many fractions round to a neighbouring cell's float. (No cell
  // boundary at 0 inside a domain: this reference would step through every float near 0, about
  // 10^9; PlaceNearZeroIsTheFirstFloatOfTheCell checks those.)
  const float ulp1024 = std::nextafter(1024.0f, 2048.0f) - 1024.0f;
  const std::vector<GridAxis> axes = {GridAxis(1),
                                      GridAxis(32),
                                      GridAxis(90, 0.0f, 1.5707964f),
                                      GridAxis(359, -3.1415927f, 3.1415927f),
                                      GridAxis(7, -3.3f, 12.9f),
                                      GridAxis(1u << 20, 0.0f, 1.0f),
                                      GridAxis(16, 1024.0f, 1024.0f + 64 * ulp1024),
                                      GridAxis(5, -1024.0f, -1024.0f + 15 * ulp1024)};
  Pcg32 rng(7);
  std::size_t cases = 0, nudged = 0;
  for (const GridAxis& a : axes) {
    for (int r = 0; r < 4000; ++r) {
      uint32_t first = rng.nextUint() % a.cells(), end = first + 1 + rng.nextUint() % (a.cells() - first);
      if (r % 4 == 0) end = first + 1;              // one cell
      if (r % 50 == 0) first = 0, end = a.cells();  // the whole axis
      const double span = end - first;
      const double k = std::floor(rng.nextDouble() * (span + 1));  // a cell boundary of the range
      const double boundary = k / span;
      for (double t : {0.0, 1.0, -0.25, 1.25, rng.nextDouble(), boundary, std::nextafter(boundary, 0.0),
                       std::nextafter(boundary, 2.0), 0.5 / span, 1.0 - 0.5 / span}) {
        const float expected = nudgedFormula(a, first, end, t);
        const float placed = a.place(first, end, t);
        ASSERT_EQ(std::bit_cast<uint32_t>(placed), std::bit_cast<uint32_t>(expected))
            << "cells " << a.cells() << " on [" << a.lo() << ", " << a.hi() << "): [" << first << ", " << end
            << ") at t = " << t << " gave " << placed << ", not " << expected;
        // placeOnGrid: the same coordinate, with the cell and grid coordinate x maps back to.
        const GridAxis::Placed onGrid = a.placeOnGrid(first, end, t);
        ASSERT_EQ(std::bit_cast<uint32_t>(onGrid.x), std::bit_cast<uint32_t>(placed));
        ASSERT_EQ(onGrid.cell, a.cellOf(placed));
        ASSERT_EQ(std::bit_cast<uint64_t>(onGrid.gridCoordinate), std::bit_cast<uint64_t>(a.gridCoordinate(placed)));
        const double g = first + std::clamp(t, 0.0, 1.0) * span;
        nudged += expected != std::clamp(static_cast<float>(a.lo() + g * a.cellWidth()), a.innerLo(), a.innerHi());
        ++cases;
      }
    }
  }
  // The rare path must have been taken, or the comparison proves nothing about it.
  EXPECT_GT(nudged, cases / 1000) << nudged << " of " << cases << " cases nudged";
}

// Domains with a cell boundary at 0, where the floats are densest: a coordinate that rounding
// carried across a boundary is moved to the first float of the cell above (t = 0) or the last of
// the cell below (t = 1), as stepping ulp by ulp would, so the float next to it on the far side
// is in the neighbouring cell.
TEST(GridAxisPlace, PlaceNearZeroIsTheFirstFloatOfTheCell) {
  std::size_t nudged = 0;
  for (const GridAxis& a : {GridAxis(360, -3.1415927f, 3.1415927f), GridAxis(2, -1.0f, 1.0f),
                            GridAxis(1000, -1.0f, 1.0f), GridAxis(6, -0.3f, 0.3f), GridAxis(180, -90.0f, 90.0f),
                            GridAxis(10, -0.7f, 0.7f), GridAxis(36, -1.3f, 1.3f)}) {
    const uint32_t middle = a.cells() / 2;
    for (uint32_t first : {middle - 1, middle}) {
      for (double t : {0.0, 1.0}) {
        const float placed = a.place(first, first + 1, t);
        ASSERT_EQ(a.cellOf(placed), first) << a.cells() << " cells, cell " << first << ", t = " << t;
        const double g = first + t;
        const float unnudged = std::clamp(static_cast<float>(a.lo() + g * a.cellWidth()), a.innerLo(), a.innerHi());
        if (placed == unnudged) continue;
        ++nudged;
        const float beyond = std::nextafter(placed, t == 0.0 ? a.lo() : a.hi());
        EXPECT_EQ(a.cellOf(beyond), t == 0.0 ? first - 1 : first + 1)
            << a.cells() << " cells, cell " << first << ", t = " << t << ": " << placed
            << " is not the cell's " << (t == 0.0 ? "first" : "last") << " float";
      }
    }
  }
  EXPECT_GT(nudged, 0u) << "no case crossed a boundary at 0: the test proves nothing";
}

}  // namespace
