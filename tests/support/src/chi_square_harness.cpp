#include "acdf/test_support/chi_square_harness.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "acdf/sampling/rng.h"

namespace acdf::test_support {
namespace {

// Per axis: how bins relate to grid cells.
struct BinAxis {
  uint32_t bins = 0;
  uint32_t cellsPerBin = 1;   // > 1: bins are unions of cells
  uint32_t binsPerCell = 1;   // > 1: bins subdivide cells
  uint32_t pointsPerBin = 1;  // midpoint-rule points per bin along this axis
};

std::vector<BinAxis> binAxes(std::span<const GridAxis> axes, const ChiSquareOptions& options) {
  if (axes.empty() || axes.size() > kMaxDims) throw std::invalid_argument("harness: bad axis count");
  if (!options.bins.empty() && options.bins.size() != axes.size())
    throw std::invalid_argument("harness: need one bin count per axis");
  if (options.subPoints == 0) throw std::invalid_argument("harness: subPoints must be >= 1");
  std::vector<BinAxis> out(axes.size());
  for (std::size_t d = 0; d < axes.size(); ++d) {
    const uint32_t cells = axes[d].cells();
    const uint32_t bins = options.bins.empty() ? cells : options.bins[d];
    BinAxis& b = out[d];
    b.bins = bins;
    if (bins == 0) throw std::invalid_argument("harness: zero bins");
    if (bins <= cells) {
      if (cells % bins != 0) throw std::invalid_argument("harness: bins must divide the cell count");
      b.cellsPerBin = cells / bins;
      b.pointsPerBin = b.cellsPerBin * options.subPoints;
    } else {
      if (bins % cells != 0) throw std::invalid_argument("harness: bins must be a multiple of cells");
      b.binsPerCell = bins / cells;
      b.pointsPerBin = options.subPoints;
    }
  }
  return out;
}

// Bin of coordinate x on an axis (x assumed inside the domain).
uint32_t binOf(const GridAxis& axis, const BinAxis& b, float x) {
  const uint32_t cell = axis.cellOf(x);
  if (b.binsPerCell == 1) return cell / b.cellsPerBin;
  // Subdivided cell: the position inside the cell, kept consistent with cellOf.
  const double within = axis.gridCoordinate(x) - cell;
  const auto sub =
      static_cast<uint32_t>(std::clamp(std::floor(within * b.binsPerCell), 0.0, double(b.binsPerCell - 1)));
  return cell * b.binsPerCell + sub;
}

// Calls f(point, binIndex, weight) for every midpoint-rule point of the bin grid.
template <class F>
void forEachQuadraturePoint(std::span<const GridAxis> axes, std::span<const BinAxis> bins, F&& f) {
  const std::size_t dims = axes.size();
  std::vector<std::vector<float>> coordinate(dims);
  std::vector<std::vector<uint32_t>> binOfPoint(dims);
  double weight = 1.0;
  for (std::size_t d = 0; d < dims; ++d) {
    const std::size_t points = std::size_t(bins[d].bins) * bins[d].pointsPerBin;
    const double lo = axes[d].lo(), width = double(axes[d].hi()) - double(axes[d].lo());
    weight *= width / double(points);
    coordinate[d].resize(points);
    binOfPoint[d].resize(points);
    for (std::size_t q = 0; q < points; ++q) {
      coordinate[d][q] = static_cast<float>(lo + (double(q) + 0.5) / double(points) * width);
      binOfPoint[d][q] = static_cast<uint32_t>(q / bins[d].pointsPerBin);
    }
  }
  std::vector<std::size_t> q(dims, 0);
  std::vector<float> x(dims);
  for (;;) {
    std::size_t bin = 0;
    for (std::size_t d = 0; d < dims; ++d) {
      x[d] = coordinate[d][q[d]];
      bin = bin * bins[d].bins + binOfPoint[d][q[d]];
    }
    f(std::span<const float>(x), bin, weight);
    std::size_t d = dims;
    while (d-- > 0) {
      if (++q[d] < coordinate[d].size()) break;
      q[d] = 0;
    }
    if (d == std::size_t(-1)) return;
  }
}

std::string describePoint(std::span<const float> x) {
  std::ostringstream s;
  s.precision(9);
  s << "(";
  for (std::size_t d = 0; d < x.size(); ++d) s << (d ? ", " : "") << x[d];
  s << ")";
  return s.str();
}

}  // namespace

bool ChiSquareReport::integralValid() const {
  return std::isfinite(pdfIntegral) && std::abs(pdfIntegral - 1.0) <= integralTolerance;
}

std::string ChiSquareReport::summary() const {
  std::ostringstream s;
  s.precision(6);
  s << "chi2=" << chi2.statistic << " dof=" << chi2.dof << " pooledCells=" << chi2.pooledCells << " p=" << chi2.pvalue
    << " (alpha=" << alpha << ", " << (chiSquarePassed() ? "pass" : "FAIL") << "); samples=" << samples
    << " outsideDomain=" << outsideDomain << " badPdf=" << badPdf << " pdfMismatch=" << pdfMismatch
    << " worstRelPdfMismatch=" << worstPdfMismatch << "; integral=" << std::setprecision(10) << pdfIntegral
    << (integralValid() ? "" : " (FAIL)");
  if (!firstProblem.empty()) s << "; first problem: " << firstProblem;
  return s.str();
}

bool checkSample(std::span<const GridAxis> axes, std::span<const float> u, const SampleND& s, const PdfFn& pdf,
                 double pdfTolerance, ChiSquareReport& report) {
  const std::size_t dims = axes.size();
  const std::span<const float> x(s.x.data(), dims);
  bool inside = true;
  for (std::size_t d = 0; d < dims; ++d) inside = inside && x[d] > axes[d].lo() && x[d] < axes[d].hi();
  if (!inside) {
    if (report.firstProblem.empty())
      report.firstProblem = "sample " + describePoint(x) + " outside the open domain, u=" + describePoint(u);
    ++report.outsideDomain;
    return false;
  }
  if (!std::isfinite(s.pdf) || !(s.pdf > 0.0f)) {
    if (report.firstProblem.empty()) {
      std::ostringstream m;
      m << "sample " << describePoint(x) << " returned pdf " << s.pdf << ", u=" << describePoint(u);
      report.firstProblem = m.str();
    }
    ++report.badPdf;
    return true;
  }
  const double evaluated = pdf(x);
  const double relative = std::abs(evaluated - double(s.pdf)) / double(s.pdf);
  report.worstPdfMismatch = std::max(report.worstPdfMismatch, relative);
  if (!(relative <= pdfTolerance)) {
    if (report.firstProblem.empty()) {
      std::ostringstream m;
      m.precision(9);
      m << "sample " << describePoint(x) << " returned pdf " << s.pdf << " but pdf(x) = " << evaluated
        << ", u=" << describePoint(u);
      report.firstProblem = m.str();
    }
    ++report.pdfMismatch;
  }
  return true;
}

ChiSquareReport runChiSquare(std::span<const GridAxis> axes, const SampleFn& sample, const PdfFn& pdf,
                             const ChiSquareOptions& options) {
  const std::vector<BinAxis> bins = binAxes(axes, options);
  const std::size_t dims = axes.size();
  std::size_t binCount = 1;
  for (const BinAxis& b : bins) binCount *= b.bins;

  ChiSquareReport report;
  report.alpha = chiSquareTestLevel(options.familyAlpha);
  report.samples = options.samples;
  report.integralTolerance = options.integralTolerance;

  // Observed counts.
  std::vector<double> observed(binCount, 0.0);
  Pcg32 rng(options.seed);
  std::vector<float> u(dims);
  for (uint64_t i = 0; i < options.samples; ++i) {
    for (float& v : u) v = rng.nextFloat();
    const SampleND s = sample(u);
    if (!checkSample(axes, u, s, pdf, options.pdfTolerance, report)) continue;
    const std::span<const float> x(s.x.data(), dims);
    std::size_t bin = 0;
    for (std::size_t d = 0; d < dims; ++d) bin = bin * bins[d].bins + binOf(axes[d], bins[d], x[d]);
    observed[bin] += 1.0;
  }

  // Expected counts: N × ∫_bin pdf.
  std::vector<double> expected(binCount, 0.0);
  double integral = 0.0;
  const double n = static_cast<double>(options.samples);
  forEachQuadraturePoint(axes, bins, [&](std::span<const float> x, std::size_t bin, double weight) {
    const double mass = double(pdf(x)) * weight;
    integral += mass;
    expected[bin] += n * mass;
  });
  report.pdfIntegral = integral;
  report.chi2 = chiSquareTest(observed, expected, 5.0);
  return report;
}

::testing::AssertionResult Passed(const ChiSquareReport& report) {
  if (report.passed()) return ::testing::AssertionSuccess() << report.summary();
  return ::testing::AssertionFailure() << report.summary();
}

void recordReport(const ChiSquareReport& report) {
  std::cout << "[ chi2     ] " << report.summary() << std::endl;
  ::testing::Test::RecordProperty("chi2_statistic", std::to_string(report.chi2.statistic));
  ::testing::Test::RecordProperty("chi2_dof", std::to_string(report.chi2.dof));
  ::testing::Test::RecordProperty("chi2_pvalue", std::to_string(report.chi2.pvalue));
  ::testing::Test::RecordProperty("chi2_alpha", std::to_string(report.alpha));
}

double integratePdf(std::span<const GridAxis> axes, const PdfFn& pdf, uint32_t subPoints) {
  ChiSquareOptions o;
  o.subPoints = subPoints;
  const std::vector<BinAxis> bins = binAxes(axes, o);
  double integral = 0.0;
  forEachQuadraturePoint(
      axes, bins, [&](std::span<const float> x, std::size_t, double weight) { integral += double(pdf(x)) * weight; });
  return integral;
}

std::vector<double> pdfCellProbabilities(std::span<const GridAxis> axes, const PdfFn& pdf) {
  ChiSquareOptions o;
  o.subPoints = 1;
  const std::vector<BinAxis> bins = binAxes(axes, o);
  std::size_t count = 1;
  for (const GridAxis& a : axes) count *= a.cells();
  std::vector<double> p(count, 0.0);
  forEachQuadraturePoint(
      axes, bins, [&](std::span<const float> x, std::size_t bin, double weight) { p[bin] += double(pdf(x)) * weight; });
  return p;
}

std::vector<double> exactCellProbabilities(std::span<const float> values) {
  const double total =
      std::accumulate(values.begin(), values.end(), 0.0, [](double a, float v) { return a + double(v); });
  std::vector<double> p(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) p[i] = double(values[i]) / total;
  return p;
}

std::vector<float> cellCentre(std::span<const GridAxis> axes, std::size_t cell) {
  std::vector<float> x(axes.size());
  for (std::size_t d = axes.size(); d-- > 0;) {
    const uint32_t k = static_cast<uint32_t>(cell % axes[d].cells());
    cell /= axes[d].cells();
    x[d] = static_cast<float>(double(axes[d].lo()) + (k + 0.5) * axes[d].cellWidth());
  }
  return x;
}

std::size_t cellIndex(std::span<const GridAxis> axes, std::span<const float> x) {
  std::size_t index = 0;
  for (std::size_t d = 0; d < axes.size(); ++d) index = index * axes[d].cells() + axes[d].cellOf(x[d]);
  return index;
}

}  // namespace acdf::test_support
