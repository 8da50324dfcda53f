// integrateReflectance (reflectance_estimator.h): the estimator's mean and variance by quadrature
// instead of sampling. Known answers on a Lambertian, agreement with the sampled estimator on the
// analytic gold GGX under its own sampler, convergence as the grid doubles, determinism, and a
// sampler whose pdf() disagrees with what it draws, which the comparison must catch.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <memory>
#include <string>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/ggx_sampler.h"
#include "acdf/brdf/lambertian.h"
#include "acdf/brdf/reflectance_estimator.h"

namespace {

using namespace acdf;

// Half the default grid per axis: gold's smooth lobe has converged there (its variance moves by
// 3e-7 relative from 512 x 64 to 2048 x 256 points). Sanitizer builds hunt memory errors: a
// coarser grid and fewer sampled runs keep them in CI's time.
#ifdef ACDF_SANITIZED_BUILD
constexpr ReflectanceQuadratureOptions kGrid{.thetaHalfPoints = 256, .phiHalfPoints = 32};
constexpr int kSeeds = 4;
#else
constexpr ReflectanceQuadratureOptions kGrid{.thetaHalfPoints = 512, .phiHalfPoints = 64};
constexpr int kSeeds = 16;
#endif

const auto kGold = std::make_shared<const AnalyticBrdf>(AnalyticBrdf::preset("gold"));

// The sampled estimator's mean and variance over kSeeds seeds, with the standard errors of their
// averages from the spread between seeds (the variance's own error needs the fourth moment).
struct SampledFigures {
  double mean = 0, variance = 0, meanError = 0, varianceError = 0;
};

SampledFigures sampleFigures(const BrdfSampler& sampler) {
  double mean = 0, meanSquares = 0, variance = 0, varianceSquares = 0;
  for (int k = 0; k < kSeeds; ++k) {
    ReflectanceEstimatorOptions o;
    o.seed = 1000 + k;
    const ReflectanceEstimate e = estimateReflectance(sampler, o);
    mean += e.mean, meanSquares += e.mean * e.mean;
    variance += e.variance, varianceSquares += e.variance * e.variance;
  }
  const auto error = [](double sum, double squares) {
    const double m = sum / kSeeds;
    return std::sqrt(std::max(0.0, squares / kSeeds - m * m) / (kSeeds - 1));
  };
  return {mean / kSeeds, variance / kSeeds, error(mean, meanSquares), error(variance, varianceSquares)};
}

// Draws what the GGX sampler draws, with its density, but pdf() answers 10% too high.
class BrokenPdfSampler final : public BrdfSampler {
 public:
  explicit BrokenPdfSampler(std::shared_ptr<const AnalyticBrdf> model) : BrdfSampler(model), ggx_(model) {}
  double pdf(const Vec3d& wo, const Vec3d& wi) const override { return 1.1 * ggx_.pdf(wo, wi); }
  std::size_t bytes() const override { return 0; }
  std::string name() const override { return "broken"; }

 protected:
  SampledDirection sampleDirection(const Vec3d& wo, float u0, float u1) const override {
    const BrdfSample s = ggx_.sample(wo, u0, u1);
    return {s.wi, s.pdf};
  }

 private:
  GgxBrdfSampler ggx_;
};

// Cosine sampling of a Lambertian weighs every sample by the albedo: mean = albedo, variance 0,
// up to the quadrature's error in ∫cosθi/π = 1 (measured: 6e-8 at 512 x 64, 1.2e-6 at 256 x 32).
TEST(ReflectanceQuadrature, LambertianUnderCosineSamplingIsExact) {
  const CosineBrdfSampler sampler(std::make_shared<const LambertianBrdf>(Rgb{0.6f, 0.6f, 0.6f}));
  const ReflectanceQuadrature q = integrateReflectance(sampler, {}, kGrid);
  EXPECT_NEAR(q.mean, 0.6, 1e-5);
  EXPECT_LT(q.variance, 1e-5);
  EXPECT_EQ(q.unsampled, 0.0);
}

// GGX gold under its own sampler: the quadrature's mean and variance within 4 standard errors of
// the sampled estimator's, and the sampled variance is far from 0, so agreement means something.
TEST(ReflectanceQuadrature, AgreesWithTheSampledEstimatorOnGgx) {
  const GgxBrdfSampler sampler(kGold);
  const ReflectanceQuadrature q = integrateReflectance(sampler, {}, kGrid);
  const SampledFigures s = sampleFigures(sampler);
  const std::string figures = "quadrature " + std::to_string(q.mean) + " / " + std::to_string(q.variance) +
                              ", sampled " + std::to_string(s.mean) + " ± " + std::to_string(s.meanError) + " / " +
                              std::to_string(s.variance) + " ± " + std::to_string(s.varianceError);
  EXPECT_NEAR(q.mean, s.mean, 4 * s.meanError + 1e-6) << figures;
  EXPECT_NEAR(q.variance, s.variance, 4 * s.varianceError) << figures;
  EXPECT_GT(s.variance, 20 * s.varianceError) << figures;
  EXPECT_EQ(q.unsampled, 0.0);
}

// A pdf() 10% off what the sampler draws: the quadrature (which trusts pdf()) and the sampled
// estimator (which uses the drawn density) must disagree, or the test above could not fail.
TEST(ReflectanceQuadrature, CatchesAPdfThatDisagreesWithTheSamples) {
  const BrokenPdfSampler sampler(kGold);
  const ReflectanceQuadrature q = integrateReflectance(sampler, {}, kGrid);
  const SampledFigures s = sampleFigures(sampler);
  EXPECT_GT(std::fabs(q.variance - s.variance), 10 * s.varianceError)
      << "quadrature " << q.variance << ", sampled " << s.variance << " ± " << s.varianceError;
}

// Doubling the grid moves the figures little: the grid above has converged for a smooth lobe.
TEST(ReflectanceQuadrature, ConvergesAsTheGridDoubles) {
  const GgxBrdfSampler sampler(kGold);
  const ReflectanceQuadrature coarse = integrateReflectance(sampler, {}, kGrid);
  const ReflectanceQuadrature fine = integrateReflectance(
      sampler, {}, {.thetaHalfPoints = 2 * kGrid.thetaHalfPoints, .phiHalfPoints = 2 * kGrid.phiHalfPoints});
  EXPECT_NEAR(coarse.mean, fine.mean, 1e-4 * fine.mean);
  EXPECT_NEAR(coarse.variance, fine.variance, 1e-3 * fine.variance);
}

// Same figures twice, and on one thread as on many: the directions' sums are combined in order.
TEST(ReflectanceQuadrature, IsDeterministicAndThreadCountFree) {
  const GgxBrdfSampler sampler(kGold);
  const ReflectanceQuadrature a = integrateReflectance(sampler, {}, kGrid);
  const ReflectanceQuadrature b = integrateReflectance(sampler, {}, kGrid);
  ReflectanceQuadrature serial;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    serial = integrateReflectance(sampler, {}, kGrid);
  }
  EXPECT_EQ(a.mean, b.mean);
  EXPECT_EQ(a.variance, b.variance);
  EXPECT_EQ(a.mean, serial.mean);
  EXPECT_EQ(a.variance, serial.variance);
}

TEST(ReflectanceQuadrature, RejectsAnEmptyGrid) {
  const GgxBrdfSampler sampler(kGold);
  EXPECT_THROW(integrateReflectance(sampler, {}, {.thetaHalfPoints = 0, .phiHalfPoints = 8}), std::invalid_argument);
  ReflectanceEstimatorOptions o;
  o.phiCount = 0;
  EXPECT_THROW(integrateReflectance(sampler, o), std::invalid_argument);
}

}  // namespace
