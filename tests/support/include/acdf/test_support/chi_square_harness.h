#pragma once
// A chi-square goodness-of-fit harness for the sampling tests.
//
// runChiSquare() draws N samples from a sampler (u from acdf::Pcg32 with a fixed seed), histograms
// them on bins that are unions of the distribution's grid cells (or subdivide them), computes each
// bin's expected count by integrating the sampler's *pdf()* over the bin (midpoint rule with
// several points per grid cell per axis — exact for pdfs constant on grid cells, and it exercises
// pdf() everywhere), and runs acdf::chiSquareTest (pools of expected >= 5).
//
// Significance: every call is one chi-square test of the program's family and runs at the level
// chiSquareTestLevel(familyAlpha) gives (chi_square_registry.h): the test that calls it must be
// registered with ACDF_CHI_SQUARE_TEST / ACDF_CHI_SQUARE_TEST_P for as many calls as it makes.
//
// Every sample is also checked: x strictly inside (lo, hi) on every axis, returned pdf finite and
// > 0, and |pdf(x) − returned pdf| <= pdfTolerance · returned pdf. The integral of pdf() over the
// domain (same midpoint rule) must be 1 within integralTolerance.

#include <gtest/gtest.h>

#include <concepts>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "acdf/sampling/chi_square.h"
#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/sample.h"
#include "acdf/test_support/chi_square_registry.h"

namespace acdf::test_support {

struct ChiSquareOptions {
  uint64_t samples = 1'000'000;
  uint64_t seed = 0x2545F4914F6CDD1DULL;
  double familyAlpha = 0.01;  // for the whole program's family of chi-square tests
  // Histogram bins per axis; empty = one bin per grid cell. Each entry must divide the axis' cell
  // count (bins are unions of cells) or be a multiple of it (bins subdivide cells).
  std::vector<uint32_t> bins;
  // Midpoint-rule points per grid cell per axis for the expected counts and the integral (per bin
  // per axis when bins subdivide cells).
  uint32_t subPoints = 2;
  double pdfTolerance = 1e-5;
  double integralTolerance = 1e-4;
};

struct ChiSquareReport {
  ChiSquareResult chi2;
  double alpha = 0;  // per-test level after the Šidák correction
  uint64_t samples = 0;
  uint64_t outsideDomain = 0;   // samples not strictly inside (lo, hi) on some axis
  uint64_t badPdf = 0;          // returned pdf not finite or <= 0
  uint64_t pdfMismatch = 0;     // |pdf(x) − returned| > tolerance · returned
  double worstPdfMismatch = 0;  // largest relative mismatch seen
  double pdfIntegral = 0;       // ∫ pdf over the domain (midpoint rule, double)
  double integralTolerance = 0;
  std::string firstProblem;  // description of the first bad sample, if any

  bool chiSquarePassed() const { return chi2.pvalue >= alpha; }
  bool samplesValid() const { return outsideDomain == 0 && badPdf == 0 && pdfMismatch == 0; }
  bool integralValid() const;
  bool passed() const { return chiSquarePassed() && samplesValid() && integralValid(); }
  std::string summary() const;
};

using SampleFn = std::function<SampleND(std::span<const float> u)>;
using PdfFn = std::function<float(std::span<const float> x)>;

// axes: the sampled axes (domain and grid cells); the sampler takes axes.size() variates.
ChiSquareReport runChiSquare(std::span<const GridAxis> axes, const SampleFn& sample, const PdfFn& pdf,
                             const ChiSquareOptions& options);

// The per-sample checks of the harness, on one sample drawn with variates u: updates the sample
// counters of `report` (and firstProblem). Returns false if x is outside the domain.
bool checkSample(std::span<const GridAxis> axes, std::span<const float> u, const SampleND& sample, const PdfFn& pdf,
                 double pdfTolerance, ChiSquareReport& report);

// Adapters so 1D samplers (float -> Sample1D, float -> float) plug in directly.
template <class F>
SampleFn toSampleFn(F f) {
  if constexpr (std::is_invocable_v<F, std::span<const float>>) {
    using R = std::invoke_result_t<F, std::span<const float>>;
    if constexpr (std::is_same_v<R, Sample1D>) {
      return [f](std::span<const float> u) {
        const Sample1D s = f(u);
        SampleND r;
        r.x[0] = s.x;
        r.pdf = s.pdf;
        return r;
      };
    } else {
      return [f](std::span<const float> u) { return SampleND(f(u)); };
    }
  } else {
    return [f](std::span<const float> u) {
      const Sample1D s = f(u[0]);
      SampleND r;
      r.x[0] = s.x;
      r.pdf = s.pdf;
      return r;
    };
  }
}

template <class F>
PdfFn toPdfFn(F f) {
  if constexpr (std::is_invocable_v<F, std::span<const float>>) {
    return [f](std::span<const float> x) { return static_cast<float>(f(x)); };
  } else {
    return [f](std::span<const float> x) { return static_cast<float>(f(x[0])); };
  }
}

template <class S, class P>
ChiSquareReport runChiSquare(std::span<const GridAxis> axes, S sample, P pdf, const ChiSquareOptions& options) {
  return runChiSquare(axes, toSampleFn(std::move(sample)), toPdfFn(std::move(pdf)), options);
}

// For EXPECT_TRUE / ASSERT_TRUE: success iff report.passed(), with the summary as the message.
::testing::AssertionResult Passed(const ChiSquareReport& report);

// Prints the report's figures to std::cout and records them as test properties.
void recordReport(const ChiSquareReport& report);

// ---- Helpers shared by the sampling tests ----------------------------------------------------

// ∫ pdf over the box spanned by `axes`, by the midpoint rule with `subPoints` points per grid cell
// per axis, accumulated in double.
double integratePdf(std::span<const GridAxis> axes, const PdfFn& pdf, uint32_t subPoints = 2);

// pdf at every grid cell's centre times the cell's volume (row-major): the cell probabilities a
// pdf that is constant on grid cells implies.
std::vector<double> pdfCellProbabilities(std::span<const GridAxis> axes, const PdfFn& pdf);

// value / Σ values in double, row-major.
std::vector<double> exactCellProbabilities(std::span<const float> values);

// The centre coordinate of every axis for the given (row-major) cell index.
std::vector<float> cellCentre(std::span<const GridAxis> axes, std::size_t cell);

// Row-major index of the grid cell holding x (axes' cellOf).
std::size_t cellIndex(std::span<const GridAxis> axes, std::span<const float> x);

}  // namespace acdf::test_support
