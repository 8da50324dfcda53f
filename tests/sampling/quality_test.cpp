// Storage and quality of the default adaptive Cascade on an environment map with a sun: it must be
// much smaller than the all-uniform cascade and stay close to the function's distribution.

#include "acdf/sampling/quality.h"

#include <gtest/gtest.h>

#include <iostream>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "acdf/fixtures/fixtures.h"
#include "acdf/sampling/cascade.h"
#include "acdf/test_support/chi_square_harness.h"
#include "acdf/test_support/samplers.h"

namespace {

using namespace acdf;
using namespace acdf::test_support;

constexpr uint32_t kWidth = 1024, kHeight = 512;

struct SunAndSky {
  std::vector<float> values = fixtures::sunAndSky(kWidth, kHeight);
  // Rows: θ ∈ [0, π) (512 cells); columns: φ ∈ [0, 2π) (1024 cells).
  std::vector<GridAxis> axes = {GridAxis(kHeight, 0.0f, std::numbers::pi_v<float>),
                                GridAxis(kWidth, 0.0f, 2 * std::numbers::pi_v<float>)};
};

const SunAndSky& sky() {
  static const SunAndSky s;
  return s;
}

TEST(Quality, AdaptiveSunAndSkyIsSmallAndClose) {
  const SunAndSky& s = sky();
  const Cascade adaptive(s.values, s.axes);
  CascadeOptions uniformOptions;
  uniformOptions.methods = {DimensionMethod::Uniform, DimensionMethod::Uniform};
  const Cascade uniform(s.values, s.axes, uniformOptions);

  const auto exact = exactCellProbabilities(s.values);
  const CompressionQuality q = compareCellProbabilities(exact, adaptive.cellProbabilities(0));
  const CompressionQuality qu = compareCellProbabilities(exact, uniform.cellProbabilities(0));
  const double ratio = double(uniform.bytes()) / double(adaptive.bytes());
  const auto intervals = adaptive.averageIntervals();
  const auto points = adaptive.pointsPerDimension();

  std::cout << "sunAndSky 1024x512, default options: adaptive " << adaptive.bytes() << " bytes, uniform "
            << uniform.bytes() << " bytes, ratio " << ratio << "\n"
            << "  chi2Divergence " << q.chi2Divergence << ", maxWeightRatio " << q.maxWeightRatio
            << ", unreachableMass " << q.unreachableMass << "\n"
            << "  average intervals θ " << intervals[0] << ", φ " << intervals[1] << "; points " << points[0] << ", "
            << points[1] << "\n"
            << "  uniform cascade: chi2Divergence " << qu.chi2Divergence << "\n";
  RecordProperty("adaptive_bytes", std::to_string(adaptive.bytes()));
  RecordProperty("uniform_bytes", std::to_string(uniform.bytes()));
  RecordProperty("size_ratio", std::to_string(ratio));
  RecordProperty("chi2_divergence", std::to_string(q.chi2Divergence));
  RecordProperty("max_weight_ratio", std::to_string(q.maxWeightRatio));

  EXPECT_GE(ratio, 20.0);
  EXPECT_LE(q.chi2Divergence, 0.05);
  EXPECT_EQ(q.unreachableMass, 0.0) << "the adaptive cascade must reach every cell of positive value";
  EXPECT_LT(qu.chi2Divergence, 1e-4) << "the uniform cascade is (nearly) exact";

  // The figures rest on cellProbabilities(): check it against pdf() on this map too.
  const Sampler sampler = makeCascade(std::make_shared<const Cascade>(s.values, s.axes));
  const auto fromPdf = pdfCellProbabilities(sampler.axes, sampler.pdf);
  const auto cells = adaptive.cellProbabilities(0);
  for (std::size_t i = 0; i < cells.size(); ++i) ASSERT_NEAR(fromPdf[i], cells[i], 2e-6 * cells[i] + 1e-30) << i;
}

ACDF_CHI_SQUARE_TEST(Quality, AdaptiveSunAndSkyPassesChiSquare, 1) {
  const SunAndSky& s = sky();
  const Sampler sampler = makeCascade(s.values, s.axes);
  ChiSquareOptions o;
  o.bins = {64, 64};  // 8 × 16 cells per bin
  o.subPoints = 1;
  const ChiSquareReport r = runChiSquare(sampler, o);
  recordReport(r);
  EXPECT_TRUE(Passed(r));
}

TEST(Quality, CompareCellProbabilities) {
  // Known values: p = (0.5, 0.5, 0), q = (0.25, 0.75, 0) → Σ p²/q − 1 = 1 + 1/3 − 1.
  const std::vector<double> p = {0.5, 0.5, 0.0}, q = {0.25, 0.75, 0.0};
  const CompressionQuality c = compareCellProbabilities(p, q);
  EXPECT_NEAR(c.chi2Divergence, 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(c.maxWeightRatio, 2.0, 1e-12);
  EXPECT_EQ(c.unreachableMass, 0.0);
  const std::vector<double> p2 = {0.2, 0.3, 0.5}, q2 = {0.5, 0.5, 0.0};
  const CompressionQuality d = compareCellProbabilities(p2, q2);
  EXPECT_NEAR(d.unreachableMass, 0.5, 1e-12);
  EXPECT_NEAR(d.maxWeightRatio, 0.6, 1e-12);
  EXPECT_GE(d.chi2Divergence, 0.0);
  const CompressionQuality same = compareCellProbabilities(p2, p2);
  EXPECT_NEAR(same.chi2Divergence, 0.0, 1e-12);
  EXPECT_NEAR(same.maxWeightRatio, 1.0, 1e-12);
}

}  // namespace
