// The lat-long mapping and the light's sampling: documented directions, a known map, zero variance
// with the uniform table, pdf/eval/sample agreement, rotation and scale, MIS compensation, the
// sun-and-sky generator, and the compression quality on the real maps.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/lat_long.h"
#include "acdf/envmap/sun_sky.h"
#include "acdf/sampling/quality.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/sample.h"
#include "envmap_test_util.h"

namespace {

using namespace acdf;
using namespace acdf::envmaptest;
constexpr double kPi = std::numbers::pi;

constexpr EnvironmentSampling kAllStrategies[] = {EnvironmentSampling::Uniform, EnvironmentSampling::Alias,
                                                  EnvironmentSampling::Adaptive, EnvironmentSampling::Compensated,
                                                  EnvironmentSampling::Hierarchical};

void expectNear(const Vec3d& a, const Vec3d& b, double tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(LatLong, DocumentedDirections) {
  expectNear(LatLongMapping::direction(0, 1.0), {0, 1, 0}, 1e-15);            // row 0: the zenith, +Y
  expectNear(LatLongMapping::direction(kPi / 2, 0), {0, 0, -1}, 1e-15);       // left edge: −Z
  expectNear(LatLongMapping::direction(kPi / 2, kPi / 2), {1, 0, 0}, 1e-15);  // a quarter in: +X
  expectNear(LatLongMapping::direction(kPi / 2, kPi), {0, 0, 1}, 1e-15);      // centre column: +Z
  expectNear(LatLongMapping::direction(kPi / 2, 1.5 * kPi), {-1, 0, 0}, 1e-15);
  for (double theta : {1e-9, 0.4, 1.6, 3.0, kPi - 1e-9})
    for (double phi : {0.0, 0.5, 3.0, 6.2}) {
      const Vec3d w = LatLongMapping::direction(theta, phi);
      EXPECT_NEAR(LatLongMapping::theta(w), theta, 1e-12);
      EXPECT_NEAR(LatLongMapping::phi(w), phi, 1e-9);
      // The z-up frame of sphere.h sees the same angles; the change of frame is a reflection.
      const Vec3d z = LatLongMapping::toZUp(w);
      EXPECT_NEAR(polarAngle(z), theta, 1e-12);
      EXPECT_NEAR(azimuth(z), phi, 1e-9);
      expectNear(LatLongMapping::fromZUp(z), w, 1e-15);
    }
  const Vec3d x = LatLongMapping::toZUp({1, 0, 0}), y = LatLongMapping::toZUp({0, 1, 0}),
              z = LatLongMapping::toZUp({0, 0, 1});
  EXPECT_NEAR(dot(cross(x, y), z), -1.0, 1e-15);  // orthogonal, determinant −1
}

TEST(LatLong, DirectionsInAPixelMapBackToIt) {
  for (auto [width, height] : {std::pair{3u, 2u}, std::pair{100u, 10u}, std::pair{4096u, 2048u}}) {
    const LatLongMapping m(width, height);
    double solidAngle = 0;
    for (uint32_t r = 0; r < height; ++r) solidAngle += m.pixelSolidAngle(r) * width;
    EXPECT_NEAR(solidAngle, 4 * kPi, 1e-12);
    const uint32_t rowStep = std::max(1u, height / 64), columnStep = std::max(1u, width / 64);
    for (uint32_t r = 0; r < height; ++r) {
      if (r % rowStep != 0 && r + 1 != height) continue;  // the first and last rows (the poles) included
      for (uint32_t c = 0; c < width; c += columnStep)
        for (double s : {0.0, 0.5, 1.0})
          for (double t : {0.0, 0.5, 1.0}) {
            const Vec3d w = m.directionInPixel({r, c}, s, t);
            ASSERT_NEAR(length(w), 1.0, 1e-15);
            ASSERT_EQ(m.pixelOf(w), (PixelIndex{r, c})) << width << "x" << height << " s " << s << " t " << t;
          }
    }
  }
}

// One lit pixel in a 100 × 10 map, at row 2 (θ ∈ [0.2π, 0.3π)) and column 30 (φ ∈ [0.6π, 0.62π)):
// every strategy samples only directions in that cell, which the eval agrees is lit.
TEST(KnownMap, OneLitPixelLightsTheDocumentedDirection) {
  const auto map = onePixelMap(100, 10, 2, 30, 7.0f);
  // Its centre by the documented formula, written out here.
  const double theta = kPi * 2.5 / 10, phi = 2 * kPi * 30.5 / 100;
  const Vec3d centre{std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
  for (EnvironmentSampling strategy : kAllStrategies) {
    const EnvironmentLight light(map, {.strategy = strategy});
    EXPECT_EQ(light.eval(centre), (Rgb{7, 7, 7}));
    EXPECT_GT(light.pdf(centre), 0.0);
    // Just outside the pixel on each side: dark and never sampled.
    for (auto [dt, dp] : {std::pair{-0.06, 0.0}, std::pair{0.06, 0.0}, std::pair{0.0, -0.07}, std::pair{0.0, 0.07}}) {
      const double t2 = theta + dt * kPi, p2 = phi + dp;
      const Vec3d w{std::sin(t2) * std::sin(p2), std::cos(t2), -std::sin(t2) * std::cos(p2)};
      EXPECT_EQ(light.eval(w), Rgb{});
      if (strategy != EnvironmentSampling::Alias) {
        EXPECT_EQ(light.pdf(w), 0.0) << toString(strategy);
      }
    }
    Pcg32 rng(7);
    for (int i = 0; i < 20000; ++i) {
      const EnvironmentSample s = light.sample(rng.nextFloat(), rng.nextFloat());
      const double sTheta = std::acos(s.direction.y);
      double sPhi = std::atan2(s.direction.x, -s.direction.z);
      if (sPhi < 0) sPhi += 2 * kPi;
      ASSERT_GE(sTheta, 0.2 * kPi);
      ASSERT_LT(sTheta, 0.3 * kPi);
      ASSERT_GE(sPhi, 0.6 * kPi);
      ASSERT_LT(sPhi, 0.62 * kPi);
      ASSERT_EQ(s.radiance, (Rgb{7, 7, 7}));
    }
  }
}

// With the uniform table and nearest lookup, L(ω) / pdf(ω) = ∫ L dω for every sample; so with
// the hierarchical warp, whose pixel probabilities are the exact ones rounded to float.
TEST(ZeroVariance, UniformTableGivesTheSameWeightForEverySample) {
  for (EnvironmentSampling strategy : {EnvironmentSampling::Uniform, EnvironmentSampling::Hierarchical})
    for (auto [width, height] : {std::pair{64u, 32u}, std::pair{3u, 2u}, std::pair{1u, 1u}, std::pair{37u, 11u}}) {
      const auto map = smoothMap(width, height);
      const double integral = map->luminanceIntegral();
      const EnvironmentLight light(map, {.strategy = strategy});
      Pcg32 rng(11);
      double worst = 0;
      for (int i = 0; i < 100000; ++i) {
        const EnvironmentSample s = light.sample(rng.nextFloat(), rng.nextFloat());
        worst = std::max(worst, std::abs(s.radiance.luminance() / s.pdf / integral - 1.0));
      }
      EXPECT_LT(worst, 1e-4) << toString(strategy) << " " << width << "x" << height;
    }
}

TEST(Sampling, PdfAndEvalAgreeWithEverySample) {
  const Image sky = sunSkyImage(128, 64, sunSkyPreset("noon"));
  const auto sunSky = std::make_shared<const EnvironmentMap>(128, 64, sky.pixels);
  for (const auto& map : {smoothMap(64, 32), sunSky, onePixelMap(3, 2, 1, 2)})
    for (EnvironmentSampling strategy : kAllStrategies) {
      const EnvironmentLight light(map, {.strategy = strategy});
      Pcg32 rng(3);
      for (int i = 0; i < 20000; ++i) {
        const float u0 = i < 2 ? 0.0f : rng.nextFloat(), u1 = i % 2 ? kOneMinusEpsilon : rng.nextFloat();
        const EnvironmentSample s = light.sample(u0, u1);
        ASSERT_TRUE(s.pdf > 0 && std::isfinite(s.pdf)) << toString(strategy);
        ASSERT_NEAR(length(s.direction), 1.0, 1e-12);
        ASSERT_EQ(light.pdf(s.direction), s.pdf) << toString(strategy) << " u " << u0 << ", " << u1;
        ASSERT_EQ(light.eval(s.direction), s.radiance);
      }
    }
}

TEST(Sampling, RotationTurnsSamplesAndScaleMultipliesRadiance) {
  const auto map = smoothMap(64, 32);
  const Rotation r = Rotation::aboutAxis({1, 2, 3}, 0.7);
  const EnvironmentLight plain(map, {.strategy = EnvironmentSampling::Adaptive});
  const EnvironmentLight turned(map, {.strategy = EnvironmentSampling::Adaptive, .worldFromMap = r, .scale = 2.5f});
  Pcg32 rng(5);
  for (int i = 0; i < 1000; ++i) {
    const float u0 = rng.nextFloat(), u1 = rng.nextFloat();
    const EnvironmentSample a = plain.sample(u0, u1), b = turned.sample(u0, u1);
    expectNear(b.direction, r.apply(a.direction), 1e-12);
    EXPECT_EQ(b.pdf, a.pdf);
    EXPECT_EQ(b.radiance, (Rgb{2.5f * a.radiance.r, 2.5f * a.radiance.g, 2.5f * a.radiance.b}));
    EXPECT_EQ(turned.pdf(r.apply(a.direction)), plain.pdf(a.direction));
  }
  // What the map shows in direction w, the turned light shows in direction R w.
  const Vec3d w = LatLongMapping::direction(1.0, 2.0);
  EXPECT_EQ(turned.eval(r.apply(w)).r, 2.5f * plain.eval(w).r);
  EXPECT_THROW(EnvironmentLight(map, {.scale = 0.0f}), std::invalid_argument);
}

TEST(Compensation, DirectionsDimmerThanTheMeanAreLeftToOtherTechniques) {
  const auto map = smoothMap(64, 32);
  const double mean = map->luminanceIntegral() / (4 * kPi);
  const EnvironmentLight light(map, {.strategy = EnvironmentSampling::Compensated});
  EXPECT_FALSE(light.compensationFellBack());
  double total = 0;
  for (double p : light.pixelProbabilities()) total += p;
  EXPECT_NEAR(total, 1.0, 1e-6);
  std::size_t dark = 0;
  for (uint32_t r = 0; r < map->height(); ++r)
    for (uint32_t c = 0; c < map->width(); ++c) {
      const Vec3d w = map->mapping().directionInPixel({r, c}, 0.5, 0.5);
      const double L = map->radiance(PixelIndex{r, c}).luminance();
      if (L < 0.999 * mean) ++dark;
      if (L > 1.001 * mean) {
        EXPECT_GT(light.pdf(w), 0.0);
      }
    }
  EXPECT_GT(dark, 0u);
  // The compensated table is zero exactly where the luminance is below the mean.
  for (std::size_t i = 0; i < light.tabulated().size(); ++i) {
    const float* v = &map->rgb()[3 * i];
    const double L = Rgb{v[0], v[1], v[2]}.luminance();
    if (L < mean * (1 - 1e-6)) {
      EXPECT_EQ(light.tabulated()[i], 0.0f) << i;
    } else if (L > mean * (1 + 1e-6)) {
      EXPECT_GT(light.tabulated()[i], 0.0f) << i;
    }
  }
}

TEST(Compensation, ConstantMapFallsBackToTheUncompensatedTable) {
  const auto map = constantMap(16, 8, 3.0f);
  const EnvironmentLight compensated(map, {.strategy = EnvironmentSampling::Compensated});
  const EnvironmentLight adaptive(map, {.strategy = EnvironmentSampling::Adaptive});
  EXPECT_TRUE(compensated.compensationFellBack());
  EXPECT_FALSE(compensated.emitsNothing());
  EXPECT_EQ(compensated.pixelProbabilities(), adaptive.pixelProbabilities());
  EXPECT_NEAR(compensated.pdf({0, 0, 1}), 1 / (4 * kPi), 1e-6);
}

TEST(SunSky, PresetsPutTheSunWhereTheySay) {
  for (const std::string& name : sunSkyPresetNames()) {
    const SunSkyParameters p = sunSkyPreset(name);
    const EnvironmentMap map(256, 128, sunSkyImage(256, 128, p).pixels);
    ASSERT_FALSE(map.isBlack()) << name;
    uint32_t brightest = 0;
    double best = -1;
    for (uint32_t i = 0; i < 256 * 128; ++i) {
      const double L = map.radiance(PixelIndex{i / 256, i % 256}).luminance();
      if (L > best) best = L, brightest = i;
    }
    if (p.sunIntensity > 0) {
      const Vec3d sun = LatLongMapping::direction(kPi / 2 - p.sunElevationDeg * kPi / 180, p.sunAzimuthDeg * kPi / 180);
      // The disk may straddle a pixel edge: the brightest pixel is the sun's or a neighbour.
      const PixelIndex at = map.mapping().pixelOf(sun);
      EXPECT_LE(std::abs(int(at.row) - int(brightest / 256)), 1) << name;
      EXPECT_LE(std::abs(int(at.column) - int(brightest % 256)), 1) << name;
      EXPECT_GT(best, 100 * map.radiance(PixelIndex{0, 0}).luminance()) << name;
    } else {
      EXPECT_EQ(brightest / 256, 0u) << name << ": without a sun the zenith is brightest";
    }
    // Below the horizon: the ground colour.
    EXPECT_EQ(map.radiance(PixelIndex{127, 3}), p.ground) << name;
  }
  EXPECT_THROW(sunSkyPreset("midnight"), std::invalid_argument);
  EXPECT_THROW(sunSkyImage(8, 4, SunSkyParameters{.sunElevationDeg = 120}), std::invalid_argument);
}

// pdf > 0 wherever the radiance is > 0: the exact probability of the lit pixels a table gives pdf 0
// (the mass a light-only estimator could never reach) is 0 for every strategy that promises it
// (all but compensated, which is for MIS), on adversarial maps and, when present, the real ones,
// at several tolerances. Float CDFs alone left up to 1.6e-9 of a real map's power unreachable.
void expectEveryLitPixelReachable(const std::shared_ptr<const EnvironmentMap>& map, const std::string& what) {
  std::vector<double> exact;
  for (float v : map->pixelPower()) exact.push_back(v);
  double total = 0;
  for (double v : exact) total += v;
  for (double& v : exact) v /= total;
  for (EnvironmentSampling strategy : {EnvironmentSampling::Uniform, EnvironmentSampling::Alias,
                                       EnvironmentSampling::Adaptive, EnvironmentSampling::Hierarchical})
    for (double epsilon : {2e-2, 2e-3, 1e-4}) {
      if (strategy != EnvironmentSampling::Adaptive && epsilon != 2e-3) continue;
      EnvironmentLightOptions options{.strategy = strategy};
      options.simplify.epsilon = epsilon;
      const EnvironmentLight light(map, options);
      const CompressionQuality q = compareCellProbabilities(exact, light.pixelProbabilities());
      EXPECT_EQ(q.unreachableMass, 0.0) << what << " " << toString(strategy) << " epsilon " << epsilon;
    }
  // The pdf the renderer sees, at every lit pixel's centre.
  const EnvironmentLight adaptive(map, {.strategy = EnvironmentSampling::Adaptive});
  std::size_t dark = 0;
  for (uint32_t r = 0; r < map->height(); ++r)
    for (uint32_t c = 0; c < map->width(); ++c)
      if (exact[std::size_t{r} * map->width() + c] > 0 &&
          !(adaptive.pdf(map->mapping().directionInPixel({r, c}, 0.5, 0.5)) > 0))
        ++dark;
  EXPECT_EQ(dark, 0u) << what << ": lit pixels of pdf 0";
}

TEST(Reachability, EveryLitPixelHasPositivePdfOnAdversarialMaps) {
  // A 1e9 sun on a sky of 1e-6: each dim pixel is far below the float CDF's resolution.
  expectEveryLitPixelReachable(makeMap(1024, 512,
                                       [](uint32_t r, uint32_t c) {
                                         const float v = (r == 100 && c == 300) ? 1e9f : 1e-6f * (1 + (r * 7 + c) % 5);
                                         return Rgb{v, v, v};
                                       }),
                               "sun on a faint sky");
  // Rows alternating between bright and faint, and a few isolated faint pixels in black rows.
  expectEveryLitPixelReachable(makeMap(512, 256,
                                       [](uint32_t r, uint32_t c) {
                                         if (r % 2 == 0) return Rgb{1e4f, 1e4f, 1e4f};
                                         const float v = (c % 97 == 0) ? 1e-5f : 0.0f;
                                         return Rgb{v, 0, 0};
                                       }),
                               "bright and faint rows");
  const Image sky = sunSkyImage(1024, 512, sunSkyPreset("sunset"));
  expectEveryLitPixelReachable(std::make_shared<const EnvironmentMap>(1024, 512, sky.pixels), "sunset preset");
}

TEST(Reachability, EveryLitPixelHasPositivePdfOnTheRealMaps) {
  ACDF_SKIP_WITHOUT_SHARED_ENVMAPS();
  for (const char* name : kSharedEnvmaps)
    expectEveryLitPixelReachable(std::make_shared<const EnvironmentMap>(EnvironmentMap::load(sharedEnvmap(name))),
                                 name);
}

constexpr double kUniformTableDivergenceBound = 1e-6;

// The uniform table is the exact distribution up to its float CDFs: the relative variance of
// L/pdf it leaves (its χ²-divergence from the exact pixel probabilities) is what lets it be
// called zero-variance, and environment_light.h states the bound this checks.
TEST(ZeroVariance, UniformTableDivergenceFromTheExactProbabilitiesIsTiny) {
  std::vector<std::pair<std::string, std::shared_ptr<const EnvironmentMap>>> maps = {
      {"noon", std::make_shared<const EnvironmentMap>(1024, 512, sunSkyImage(1024, 512, sunSkyPreset("noon")).pixels)},
      {"smooth", smoothMap(256, 128)}};
  if (!sharedEnvmap(kSharedEnvmaps[0]).empty())
    for (const char* name : kSharedEnvmaps)
      maps.emplace_back(name, std::make_shared<const EnvironmentMap>(EnvironmentMap::load(sharedEnvmap(name))));
  for (const auto& [name, map] : maps) {
    const EnvironmentLight uniform(map, {.strategy = EnvironmentSampling::Uniform});
    std::vector<double> exact(uniform.tabulated().begin(), uniform.tabulated().end());
    double total = 0;
    for (double v : exact) total += v;
    for (double& v : exact) v /= total;
    const CompressionQuality q = compareCellProbabilities(exact, uniform.pixelProbabilities());
    std::cout << name << ": uniform table divergence " << q.chi2Divergence << "\n";
    EXPECT_LT(q.chi2Divergence, kUniformTableDivergenceBound) << name;
  }
}

// The quality bar: on each real map the default adaptive table is at least 10× smaller
// than the uniform one, for a χ²-divergence of at most 0.1.
TEST(Quality, AdaptiveTablesOfTheRealMapsAreSmallAndAccurate) {
  ACDF_SKIP_WITHOUT_SHARED_ENVMAPS();
  for (const char* name : kSharedEnvmaps) {
    const auto map = std::make_shared<const EnvironmentMap>(EnvironmentMap::load(sharedEnvmap(name)));
    const EnvironmentLight uniform(map, {.strategy = EnvironmentSampling::Uniform});
    const EnvironmentLight adaptive(map, {.strategy = EnvironmentSampling::Adaptive});
    std::vector<double> exact(adaptive.tabulated().begin(), adaptive.tabulated().end());
    double total = 0;
    for (double v : exact) total += v;
    for (double& v : exact) v /= total;
    const CompressionQuality q = compareCellProbabilities(exact, adaptive.pixelProbabilities());
    const double compression = double(uniform.tableBytes()) / double(adaptive.tableBytes());
    std::cout << name << ": compression " << compression << "x, chi2 divergence " << q.chi2Divergence
              << ", max weight ratio " << q.maxWeightRatio << "\n";
    EXPECT_GE(compression, 10.0) << name;
    EXPECT_LE(q.chi2Divergence, 0.1) << name;
    EXPECT_EQ(q.unreachableMass, 0.0) << name;
  }
}

}  // namespace
