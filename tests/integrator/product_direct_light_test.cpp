// ProductDirectLight at single shading points, without a renderer: with one candidate it is plain
// mixture sampling (a chi-square test of the chosen direction against the mixture's pdf, and the
// estimate is the integrand over that pdf); with any number of candidates and any mixture the
// estimator's mean is ∫ f L cos dω by quadrature; no input makes it return a non-finite value.

#include <array>
#include <bit>
#include <functional>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/ggx_sampler.h"
#include "acdf/brdf/lambertian.h"
#include "acdf/envmap/lat_long.h"
#include "acdf/integrator/product_direct_light.h"
#include "acdf/sampling/sphere_chi_square.h"
#include "acdf/test_support/chi_square_registry.h"

namespace acdf {
namespace {

constexpr double kPi = std::numbers::pi;

std::shared_ptr<const EnvironmentMap> makeMap(uint32_t width, uint32_t height,
                                              const std::function<Rgb(uint32_t row, uint32_t column)>& rgb) {
  std::vector<float> pixels;
  for (uint32_t r = 0; r < height; ++r)
    for (uint32_t c = 0; c < width; ++c) {
      const Rgb v = rgb(r, c);
      pixels.insert(pixels.end(), {v.r, v.g, v.b});
    }
  return std::make_shared<const EnvironmentMap>(width, height, std::move(pixels));
}

// Positive everywhere, different in every channel, brighter towards the zenith (+Y).
std::shared_ptr<const EnvironmentMap> skyMap() {
  return makeMap(32, 16, [](uint32_t r, uint32_t c) {
    const float up = 1.0f - static_cast<float>(r) / 16, around = 0.5f + 0.5f * std::sin(0.4f * c);
    return Rgb{0.2f + up, 0.3f + 0.5f * up * around, 0.5f + 0.2f * around};
  });
}

constexpr uint32_t kSunRow = 4, kSunColumn = 5;
// A reddish sky and a blue sun a thousand times brighter in one pixel. The colours differ so that
// the estimate's channels, f ⊙ L cos / p̂ (p̂ their luminance), depend on which candidate is kept:
// a resampling choice of the wrong law biases them.
std::shared_ptr<const EnvironmentMap> sunMap() {
  const auto sky = skyMap();
  return makeMap(32, 16, [&](uint32_t r, uint32_t c) {
    const Rgb s = sky->radiance(PixelIndex{r, c});
    return r == kSunRow && c == kSunColumn ? Rgb{200, 300, 5000} : Rgb{s.r, 0.3f * s.g, 0.05f * s.b};
  });
}

Vec3d sunDirection() {
  return LatLongMapping::direction(kPi * (kSunRow + 0.5) / 16, 2 * kPi * (kSunColumn + 0.5) / 32);
}

std::shared_ptr<const BrdfSampler> gold() {
  return std::make_shared<GgxBrdfSampler>(std::make_shared<const AnalyticBrdf>(AnalyticBrdf::preset("gold")));
}
std::shared_ptr<const BrdfSampler> diffuse() {
  return std::make_shared<CosineBrdfSampler>(std::make_shared<LambertianBrdf>(Rgb{0.8f, 0.5f, 0.2f}));
}

std::shared_ptr<const EnvironmentLight> light(std::shared_ptr<const EnvironmentMap> map, EnvironmentSampling strategy) {
  EnvironmentLightOptions options;
  options.strategy = strategy;
  options.local.blockSize = 2;
  return std::make_shared<const EnvironmentLight>(std::move(map), options);
}

LightSampleContext contextFor(const Vec3d& normal, const ProductSamplingOptions& options) {
  return {.allowIncompletePdf = options.bsdfFraction > 0, .normal = normal};
}

// The variates of one draw from the two a test harness gives.
Pcg32 streamOf(float u0, float u1) {
  return Pcg32((uint64_t{std::bit_cast<uint32_t>(u0)} << 32) | std::bit_cast<uint32_t>(u1));
}

// ∫ g(ω) dω over the map's pixels, K × K points per pixel uniform in solid angle.
double integrateOverPixels(const LatLongMapping& mapping, uint32_t K, const std::function<double(const Vec3d&)>& g) {
  double sum = 0;
  for (uint32_t r = 0; r < mapping.height(); ++r) {
    const double solidAngle =
        (std::cos(kPi * r / mapping.height()) - std::cos(kPi * (r + 1) / mapping.height())) * 2 * kPi / mapping.width();
    for (uint32_t c = 0; c < mapping.width(); ++c)
      for (uint32_t i = 0; i < K; ++i)
        for (uint32_t j = 0; j < K; ++j)
          sum += g(mapping.directionInPixel({r, c}, (i + 0.5) / K, (j + 0.5) / K)) * solidAngle / (K * K);
  }
  return sum;
}

// With M = 1 the chosen direction is the candidate, drawn from the mixture q, and kept when
// p̂ > 0: on a positive map with a diffuse material, when it is above the horizon (the local
// table's cosine bound covers a whole cell of normals, so a few light candidates fall below).
// So draws repeated until one is kept follow q(ω) · 1{n · ω > 0} / Z, Z = ∫ q over the upper
// hemisphere. Binned in the map's (θ, φ), so that the light's piecewise-constant density is
// integrated exactly; the normals' horizons lie on bin edges (a bin cut by the horizon could
// have all its quadrature points below it and expect no samples).
ACDF_CHI_SQUARE_TEST(ProductDirectLight, OneCandidateSamplesTheMixture, 2) {
  const auto material = diffuse();
  const auto env = light(skyMap(), EnvironmentSampling::Local);
  for (const Vec3d normal : {Vec3d{0, 1, 0}, Vec3d{1, 0, 0}}) {
    const ProductSamplingOptions options{.candidates = 1, .bsdfFraction = 0.3};
    const Frame frame(normal);
    const ProductDirectLight technique(*env, contextFor(normal, options), *material, frame,
                                       normalize(Vec3d{0.3, 0.1, 0.9}), options);
    auto keptPdf = [&](const Vec3d& w) { return dot(w, normal) > 0 ? technique.mixturePdf(w) : 0.0; };
    const double kept = integrateOverPixels(env->map().mapping(), 16, keptPdf);
    EXPECT_GT(kept, 0.9);
    SphereChiSquareOptions chi;
    chi.thetaBins = 32;
    chi.phiBins = 64;
    chi.alpha = test_support::chiSquareTestLevel();
    const SphereChiSquareReport report = sphereChiSquareTest(
        [&](float u0, float u1) -> DirectionSample {
          CandidateValues values(streamOf(u0, u1));
          for (int attempt = 0; attempt < 1000; ++attempt)
            if (const auto s = technique.sample(values))
              return {LatLongMapping::toZUp(s->direction), s->mixturePdf / kept};
          return {};
        },
        [&](const Vec3d& w) { return keptPdf(LatLongMapping::fromZUp(w)) / kept; }, chi);
    EXPECT_TRUE(report.passed()) << report.summary();
    EXPECT_NEAR(report.pdfIntegral, 1.0, 1e-3);
  }
}

// With M = 1 the estimate is f L cos / q at the chosen direction, q as mixturePdf() computes it.
TEST(ProductDirectLight, OneCandidateEstimateIsIntegrandOverMixturePdf) {
  const auto material = gold();
  const auto env = light(sunMap(), EnvironmentSampling::Compensated);
  const Vec3d normal = normalize(Vec3d{0.2, 1, 0.3});
  const Frame frame(normal);
  const Vec3d wo = frame.toLocal(reflect(sunDirection(), normal));
  const ProductSamplingOptions options{.candidates = 1, .bsdfFraction = 0.5};
  const ProductDirectLight technique(*env, contextFor(normal, options), *material, frame, wo, options);
  CandidateValues values(Pcg32(11));
  int returned = 0;
  for (int i = 0; i < 20000; ++i) {
    const auto s = technique.sample(values);
    if (!s) continue;
    ++returned;
    const double q = technique.mixturePdf(s->direction);
    ASSERT_NEAR(s->mixturePdf, q, BrdfSampler::kPdfRoundTrip * q) << "sample " << i;
    const Vec3d wi = frame.toLocal(s->direction);
    const Rgb integrand = material->eval(wo, wi) * env->eval(s->direction) * static_cast<float>(wi.z);
    for (auto [value, exact] : {std::pair{s->estimate.r, integrand.r}, std::pair{s->estimate.g, integrand.g},
                                std::pair{s->estimate.b, integrand.b}})
      ASSERT_NEAR(value, exact / q, 2e-4 * exact / q) << "sample " << i;
  }
  EXPECT_GT(returned, 10000);
}

// ∫ f(ωo, ω) L(ω) max(0, cosθ) dω, per channel.
std::array<double, 3> integrate(const EnvironmentLight& env, const BrdfSampler& material, const Frame& frame,
                                const Vec3d& wo) {
  std::array<double, 3> sum{};
  for (int k = 0; k < 3; ++k)
    sum[k] = integrateOverPixels(env.map().mapping(), 32, [&](const Vec3d& w) {
      const Vec3d wi = frame.toLocal(w);
      if (wi.z <= 0) return 0.0;
      const Rgb f = material.eval(wo, wi) * env.eval(w);
      return (k == 0 ? f.r : k == 1 ? f.g : f.b) * wi.z;
    });
  return sum;
}

struct MeanCase {
  uint32_t candidates;
  double bsdfFraction;
  EnvironmentSampling strategy;
  bool sobol = false;  // candidates' points from one padded Sobol component, as SobolSampler gives them
};

class ProductEstimatorMean : public ::testing::TestWithParam<MeanCase> {};

// A glossy lobe aimed at a small sun over a sky: the estimator's mean over 10^5 shading-point
// estimates is the integral, within 4 standard errors and the quadrature's 0.2 %. Dropping 1/M,
// or weighting by one strategy's density instead of the mixture's, misses by far more. With Sobol
// points, estimate n's candidates are points nM … nM + M − 1 of one sequence and its resampling
// value point n of another: dependent, each of law q, so still unbiased; the standard error is
// then that of independent estimates, an upper bound.
TEST_P(ProductEstimatorMean, IsTheIntegral) {
  const MeanCase c = GetParam();
  const auto material = gold();
  const auto env = light(sunMap(), c.strategy);
  const Vec3d normal = normalize(Vec3d{0.2, 1, 0.3});
  const Frame frame(normal);
  const Vec3d wo = frame.toLocal(reflect(normalize(sunDirection() + Vec3d{0.05, 0, 0}), normal));
  const ProductSamplingOptions options{.candidates = c.candidates, .bsdfFraction = c.bsdfFraction};
  const ProductDirectLight technique(*env, contextFor(normal, options), *material, frame, wo, options);
  const std::array<double, 3> exact = integrate(*env, *material, frame, wo);

  const int n = 100000;
  std::array<double, 3> sum{}, sumSq{};
  CandidateValues independent(Pcg32(5));
  for (int i = 0; i < n; ++i) {
    CandidateValues stratified(Pcg32(i), 17, i, c.candidates, 3);
    const auto s = technique.sample(c.sobol ? stratified : independent);
    if (!s) continue;
    const double v[3] = {s->estimate.r, s->estimate.g, s->estimate.b};
    for (int k = 0; k < 3; ++k) sum[k] += v[k], sumSq[k] += v[k] * v[k];
  }
  for (int k = 0; k < 3; ++k) {
    const double mean = sum[k] / n, se = std::sqrt((sumSq[k] / n - mean * mean) / (n - 1));
    EXPECT_NEAR(mean, exact[k], 4 * se + 2e-3 * exact[k]) << "channel " << k << ", standard error " << se;
    EXPECT_LT(se, 0.02 * exact[k]) << "channel " << k << ": the error bar must be meaningful";
  }
}

INSTANTIATE_TEST_SUITE_P(
    CandidatesAndMixtures, ProductEstimatorMean,
    ::testing::Values(MeanCase{1, 0.5, EnvironmentSampling::Compensated},
                      MeanCase{8, 0.5, EnvironmentSampling::Compensated}, MeanCase{8, 0, EnvironmentSampling::Adaptive},
                      MeanCase{8, 1, EnvironmentSampling::Adaptive}, MeanCase{4, 0.5, EnvironmentSampling::Local},
                      MeanCase{16, 0.2, EnvironmentSampling::UniformSphere},
                      MeanCase{1, 0.5, EnvironmentSampling::Compensated, true},
                      MeanCase{8, 0.5, EnvironmentSampling::Compensated, true},
                      MeanCase{8, 0, EnvironmentSampling::Local, true}),
    [](const auto& info) {
      std::string name = "M" + std::to_string(info.param.candidates) + "_b" +
                         std::to_string(static_cast<int>(info.param.bsdfFraction * 10)) + "_" +
                         std::string(toString(info.param.strategy)) + (info.param.sobol ? "_sobol" : "");
      for (char& ch : name)
        if (ch == '-') ch = '_';
      return name;
    });

// Black maps, a single-pixel sun of 1e9, grazing and horizontal ωo, normals at the map's poles,
// along its seam and on the local table's cell edges, a material that is zero over nearly all of
// the hemisphere (GGX α = 0.002) beside a sharp and a diffuse one, every mixture: every returned
// estimate is finite and >= 0 with a finite positive pdf, over 1e7 shading points (2e5 under the
// sanitizers).
TEST(ProductDirectLight, NoNonFiniteValuesOnAdversarialInputs) {
  const std::vector<std::shared_ptr<const EnvironmentMap>> maps = {
      makeMap(32, 16, [](uint32_t, uint32_t) { return Rgb{}; }),
      makeMap(64, 32, [](uint32_t r, uint32_t c) { return r == 0 && c == 7 ? Rgb{1e9f, 1e9f, 1e9f} : Rgb{}; }),
      makeMap(64, 32,
              [](uint32_t r, uint32_t c) { return r == 20 && c == 40 ? Rgb{1e9f, 5e8f, 1e8f} : Rgb{1e-6f, 0, 0}; }),
  };
  // The default local table has 32 × 64 normal cells: θ = 8π/32 and φ = 16 · 2π/64 are cell edges.
  const LocalEnvironmentOptions cells;
  const std::vector<Vec3d> normals = {{0, 1, 0},
                                      {0, -1, 0},
                                      {0, 0, -1},
                                      {1e-9, 1, 0},
                                      normalize(Vec3d{0, 0.3, -1}),
                                      LatLongMapping::direction(8 * kPi / cells.normalRows, 0.3),
                                      LatLongMapping::direction(8 * kPi / cells.normalRows, 32 * kPi / cells.normalColumns)};
  const std::vector<std::shared_ptr<const BrdfSampler>> materials = {
      gold(), diffuse(),
      std::make_shared<GgxBrdfSampler>(std::make_shared<const AnalyticBrdf>(AnalyticBrdf::conductor(0.002, {0.9, 0.9, 0.9})))};
#ifdef ACDF_SANITIZED_BUILD
  constexpr int kDrawsPerInput = 140;
#else
  constexpr int kDrawsPerInput = 6700;
#endif
  const std::vector<Vec3d> outgoing = {
      {0, 0, 1}, normalize(Vec3d{1, 0, 1e-7}), {1, 0, 0}, normalize(Vec3d{0.3, 0.4, 0.5})};
  CandidateValues values(Pcg32(3));
  long estimates = 0, nonZero = 0;
  for (const auto& map : maps)
    for (EnvironmentSampling strategy : {EnvironmentSampling::Compensated, EnvironmentSampling::Local})
      for (const auto& material : materials) {
        const auto env = light(map, strategy);
        for (double b : {0.0, 0.5, 1.0})
          for (const Vec3d& normal : normals)
            for (const Vec3d& wo : outgoing) {
              const ProductSamplingOptions options{.candidates = 4, .bsdfFraction = b};
              const Frame frame(normal);
              const ProductDirectLight technique(*env, contextFor(normal, options), *material, frame, wo, options);
              for (int i = 0; i < kDrawsPerInput; ++i) {
                const auto s = technique.sample(values);
                ++estimates;
                if (!s) continue;
                ++nonZero;
                for (float v : {s->estimate.r, s->estimate.g, s->estimate.b})
                  ASSERT_TRUE(std::isfinite(v) && v >= 0) << "estimate " << v;
                ASSERT_TRUE(std::isfinite(s->mixturePdf) && s->mixturePdf > 0) << "pdf " << s->mixturePdf;
                ASSERT_NEAR(length(s->direction), 1.0, 1e-6);
              }
            }
      }
  EXPECT_GT(nonZero, estimates / 10) << "most inputs must light something";
#ifndef ACDF_SANITIZED_BUILD
  EXPECT_GE(estimates, 10'000'000);
#endif
}

TEST(ProductDirectLight, OptionsAreValidated) {
  EXPECT_THROW(validate(ProductSamplingOptions{.candidates = 0}), OptionError);
  EXPECT_THROW(validate(ProductSamplingOptions{.candidates = 1025}), OptionError);
  EXPECT_THROW(validate(ProductSamplingOptions{.bsdfFraction = -0.1}), OptionError);
  EXPECT_THROW(validate(ProductSamplingOptions{.bsdfFraction = std::nan("")}), OptionError);
  EXPECT_NO_THROW(validate(ProductSamplingOptions{.candidates = 1, .bsdfFraction = 1}));
}

}  // namespace
}  // namespace acdf
