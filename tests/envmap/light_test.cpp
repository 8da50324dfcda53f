// The lat-long mapping (pixelOf exactly its angle formula) and the light's sampling: documented
// directions, a known map, zero variance with the uniform table, pdf/eval/sample agreement,
// rotation and scale, uniform-sphere sampling, MIS compensation and the table each call uses,
// lights sharing tables, the sun-and-sky generator, and the compression quality on the real maps.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <stdexcept>
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

constexpr LightSampleContext kComplete{.allowIncompletePdf = false}, kIncomplete{.allowIncompletePdf = true};

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

// pixelOf is pixelByAngles, exactly: on random directions of any length, directions on and a hair
// off every pixel edge (seam and poles included), axes with zeros of either sign, subnormal and huge
// components, at several sizes.
TEST(LatLong, PixelOfIsThePixelOfTheAngles) {
  for (const auto& [width, height] : std::vector<std::pair<uint32_t, uint32_t>>{
           {64, 32}, {7, 5}, {1, 1}, {2, 1}, {3, 2}, {4, 4}, {4096, 3}, {5, 4096}, {1024, 512}}) {
    const LatLongMapping m(width, height);
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    uint64_t checked = 0;
    auto check = [&](const Vec3d& w) {
      ASSERT_EQ(m.pixelOf(w), m.pixelByAngles(w)) << size << " direction " << w.x << " " << w.y << " " << w.z;
      ++checked;
    };
    auto randomDirection = [](Pcg32& rng) { return sampleUniformSphere(rng.nextFloat(), rng.nextFloat()); };
    Pcg32 rng(width * 7919 + height);
    for (int i = 0; i < 100000; ++i) check(randomDirection(rng) * std::pow(10.0, -200 + 400 * rng.nextDouble()));
    const std::vector<double> offsets = {0, 1e-16, -1e-16, 1e-13, -1e-13, 1e-10, -1e-10, 1e-9, -1e-9, 1e-8, -1e-8};
    const uint32_t edgeRows = std::min(height, 64u), edgeColumns = std::min(width, 128u);
    for (uint32_t r = 0; r <= edgeRows; ++r)
      for (uint32_t c = 0; c <= edgeColumns; ++c)
        for (double dt : offsets)
          for (double dp : offsets) {
            const Vec3d w = LatLongMapping::direction(kPi * r / edgeRows + dt, 2 * kPi * c / edgeColumns + dp);
            check(w);
            check(w * 1e-150);
            check(w * 1e150);
          }
    for (double x : {0.0, -0.0})
      for (double y : {1.0, -1.0, 1e-300, -1e300})
        for (double z : {0.0, -0.0}) check({x, y, z});
    // One zero of either sign among random components.
    for (int i = 0; i < 3000; ++i) {
      const Vec3d v = randomDirection(rng) * std::pow(10.0, -150 + 300 * rng.nextDouble());
      const double zero = i % 2 ? 0.0 : -0.0;
      check({zero, v.y, v.z});
      check({v.x, zero, v.z});
      check({v.x, v.y, zero});
      check({zero, zero, v.z});
      check({v.x, zero, zero});
      check({zero, v.y, zero});
    }
    for (double tiny : {5e-324, -5e-324, 1e-310, -1e-310, 1e-160, -1e-160})
      for (const Vec3d& w : {Vec3d{tiny, 1, 0}, Vec3d{0, 1, tiny}, Vec3d{tiny, -1, -0.0}, Vec3d{tiny, 0, tiny},
                             Vec3d{1, tiny, 0}, Vec3d{0, tiny, -1}, Vec3d{tiny, tiny, tiny}, Vec3d{1e300, tiny, 1e300}})
        check(w);
    EXPECT_GT(checked, 100000u);
  }
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
// every table strategy samples only directions in that cell, which the eval agrees is lit.
TEST(KnownMap, OneLitPixelLightsTheDocumentedDirection) {
  const auto map = onePixelMap(100, 10, 2, 30, 7.0f);
  // Its centre by the documented formula, written out here.
  const double theta = kPi * 2.5 / 10, phi = 2 * kPi * 30.5 / 100;
  const Vec3d centre{std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
  for (EnvironmentSampling strategy : kTableStrategies)
    for (const LightSampleContext& context : kLightContexts) {
      SCOPED_TRACE(std::string(toString(strategy)) + ", " + describe(context));
      const EnvironmentLight light(map, {.strategy = strategy});
      EXPECT_EQ(light.eval(centre), (Rgb{7, 7, 7}));
      EXPECT_GT(light.pdf(context, centre), 0.0);
      // Just outside the pixel on each side: dark and never sampled.
      for (auto [dt, dp] : {std::pair{-0.06, 0.0}, std::pair{0.06, 0.0}, std::pair{0.0, -0.07}, std::pair{0.0, 0.07}}) {
        const double t2 = theta + dt * kPi, p2 = phi + dp;
        const Vec3d w{std::sin(t2) * std::sin(p2), std::cos(t2), -std::sin(t2) * std::cos(p2)};
        EXPECT_EQ(light.eval(w), Rgb{});
        if (strategy != EnvironmentSampling::Alias) {
          EXPECT_EQ(light.pdf(context, w), 0.0);
        }
      }
      Pcg32 rng(7);
      for (int i = 0; i < 20000; ++i) {
        const LightSample s = light.sample(context, rng.nextFloat(), rng.nextFloat());
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
        const LightSample s = light.sample({}, rng.nextFloat(), rng.nextFloat());
        worst = std::max(worst, std::abs(s.radiance.luminance() / s.pdf / integral - 1.0));
      }
      EXPECT_LT(worst, 1e-4) << toString(strategy) << " " << width << "x" << height;
    }
}

TEST(Sampling, PdfAndEvalAgreeWithEverySample) {
  const Image sky = sunSkyImage(128, 64, sunSkyPreset("noon"));
  const auto sunSky = std::make_shared<const EnvironmentMap>(128, 64, sky.pixels);
  // A row of pixels near float's maximum: the row's power overflows float (found by fuzz_image:
  // the alias strategy's row table threw from inside the light's constructor).
  std::vector<float> nearMax(4 * 2 * 3, 1.0f);
  std::fill_n(nearMax.begin(), 4 * 3, 3e38f);  // the top row: each pixel's power at float's maximum
  const auto huge = std::make_shared<const EnvironmentMap>(4, 2, nearMax);
  for (const auto& map : {smoothMap(64, 32), sunSky, onePixelMap(3, 2, 1, 2), huge})
    for (EnvironmentSampling strategy : kEnvironmentSamplings) {
      const EnvironmentLight light(map, {.strategy = strategy});
      for (const LightSampleContext& context : kLightContexts) {
        SCOPED_TRACE(std::string(toString(strategy)) + ", " + describe(context));
        Pcg32 rng(3);
        for (int i = 0; i < 20000; ++i) {
          const float u0 = i < 2 ? 0.0f : rng.nextFloat(), u1 = i % 2 ? kOneMinusEpsilon : rng.nextFloat();
          const LightSample s = light.sample(context, u0, u1);
          ASSERT_TRUE(s.pdf > 0 && std::isfinite(s.pdf));
          ASSERT_NEAR(length(s.direction), 1.0, 1e-12);
          ASSERT_EQ(light.pdf(context, s.direction), s.pdf) << "u " << u0 << ", " << u1;
          ASSERT_EQ(light.eval(s.direction), s.radiance);
        }
      }
    }
}

// evalWithPdf is eval and pdf in one call, bit for bit, for every strategy and kind of call (Local's
// with a normal too), on lit, one-pixel and black maps turned into the world.
TEST(Sampling, EvalWithPdfIsEvalAndPdf) {
  const Rotation r = Rotation::aboutAxis({1, 2, 3}, 0.7);
  for (const auto& map : {smoothMap(64, 32), onePixelMap(3, 2, 1, 2), constantMap(8, 4, 0.0f)})
    for (EnvironmentSampling strategy : kEnvironmentSamplings) {
      const EnvironmentLight light(map, {.strategy = strategy, .worldFromMap = r, .scale = 1.5f});
      std::vector<LightSampleContext> contexts(std::begin(kLightContexts), std::end(kLightContexts));
      contexts.push_back({.allowIncompletePdf = true, .normal = Vec3d{0.3, -0.5, 0.8}});
      for (const LightSampleContext& context : contexts) {
        SCOPED_TRACE(std::string(toString(strategy)) + ", " + describe(context) + (context.normal ? ", normal" : ""));
        Pcg32 rng(4);
        for (int i = 0; i < 2000; ++i) {
          const Vec3d w = sampleUniformSphere(rng.nextDouble(), rng.nextDouble()) * 3.0;
          const RadianceAndPdf both = light.evalWithPdf(context, w);
          ASSERT_EQ(both.radiance, light.eval(w));
          ASSERT_EQ(both.pdf, light.pdf(context, w));
        }
      }
    }
}

// prefetch() keeps w's pixel in the context for evalWithPdf: the same answer bit for bit, and used
// only for that direction and from that light (a light turned otherwise finds its own pixel).
TEST(Sampling, APrefetchedPixelServesOnlyItsDirectionAndLight) {
  const auto map = smoothMap(64, 32);
  const EnvironmentLight light(map, {.strategy = EnvironmentSampling::Compensated});
  const EnvironmentLight turned(map, {.strategy = EnvironmentSampling::Compensated,
                                      .worldFromMap = Rotation::aboutAxis({1, 2, 3}, 0.7)});
  auto expectSame = [](const RadianceAndPdf& a, const RadianceAndPdf& b) {
    ASSERT_EQ(a.radiance, b.radiance);
    ASSERT_EQ(a.pdf, b.pdf);
  };
  Pcg32 rng(6);
  for (int i = 0; i < 2000; ++i) {
    const Vec3d w = sampleUniformSphere(rng.nextDouble(), rng.nextDouble());
    const Vec3d other = sampleUniformSphere(rng.nextDouble(), rng.nextDouble());
    for (const bool incomplete : {false, true}) {
      LightSampleContext context{.allowIncompletePdf = incomplete};
      light.prefetch(context, w);
      expectSame(light.evalWithPdf(context, w), light.evalWithPdf({.allowIncompletePdf = incomplete}, w));
      expectSame(light.evalWithPdf(context, other), light.evalWithPdf({.allowIncompletePdf = incomplete}, other));
      expectSame(turned.evalWithPdf(context, w), turned.evalWithPdf({.allowIncompletePdf = incomplete}, w));
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
    const LightSample a = plain.sample({}, u0, u1), b = turned.sample({}, u0, u1);
    expectNear(b.direction, r.apply(a.direction), 1e-12);
    EXPECT_EQ(b.pdf, a.pdf);
    EXPECT_EQ(b.radiance, (Rgb{2.5f * a.radiance.r, 2.5f * a.radiance.g, 2.5f * a.radiance.b}));
    EXPECT_EQ(turned.pdf({}, r.apply(a.direction)), plain.pdf({}, a.direction));
  }
  // What the map shows in direction w, the turned light shows in direction R w.
  const Vec3d w = LatLongMapping::direction(1.0, 2.0);
  EXPECT_EQ(turned.eval(r.apply(w)).r, 2.5f * plain.eval(w).r);
  EXPECT_THROW(EnvironmentLight(map, {.scale = 0.0f}), std::invalid_argument);
}

TEST(UniformSphere, SamplesTheSphereWithoutATable) {
  const auto map = smoothMap(64, 32);
  const Rotation r = Rotation::aboutAxis({1, 2, 3}, 0.7);
  const EnvironmentLight light(map, {.strategy = EnvironmentSampling::UniformSphere, .worldFromMap = r});
  EXPECT_EQ(light.tableBytes(), 0u);
  EXPECT_TRUE(light.table({}).tabulated().empty());
  EXPECT_FALSE(light.emitsNothing());
  Pcg32 rng(9);
  Vec3d mean{};
  for (int i = 0; i < 100000; ++i) {
    const LightSample s = light.sample({}, rng.nextFloat(), rng.nextFloat());
    ASSERT_EQ(s.pdf, kUniformSpherePdf);
    ASSERT_EQ(s.radiance, light.eval(s.direction));
    mean = mean + s.direction * 1e-5;
  }
  // The mean direction of 1e5 uniform ones: each coordinate has standard deviation 1/√(3·1e5).
  EXPECT_LT(length(mean), 5 * std::sqrt(1.0 / 3e5));
  EXPECT_EQ(light.pdf({}, {0, 0, 1}), kUniformSpherePdf);
  // A black map emits nothing whatever the strategy.
  const EnvironmentLight black(constantMap(8, 4, 0.0f), {.strategy = EnvironmentSampling::UniformSphere});
  EXPECT_TRUE(black.emitsNothing());
  EXPECT_EQ(black.sample({}, 0.5f, 0.5f).pdf, 0.0);
  EXPECT_EQ(black.pdf({}, {0, 1, 0}), 0.0);
}

TEST(Compensation, DirectionsDimmerThanTheMeanAreLeftToOtherTechniques) {
  const auto map = smoothMap(64, 32);
  const double mean = map->luminanceIntegral() / (4 * kPi);
  const EnvironmentLight light(map, {.strategy = EnvironmentSampling::Compensated});
  const EnvironmentTable& table = light.table(kIncomplete);
  EXPECT_EQ(table.strategy(), EnvironmentTableStrategy::Compensated);
  EXPECT_FALSE(table.compensationFellBack());
  EXPECT_FALSE(table.complete());
  double total = 0;
  for (double p : table.pixelProbabilities()) total += p;
  EXPECT_NEAR(total, 1.0, 1e-6);
  std::size_t dark = 0;
  for (uint32_t r = 0; r < map->height(); ++r)
    for (uint32_t c = 0; c < map->width(); ++c) {
      const Vec3d w = map->mapping().directionInPixel({r, c}, 0.5, 0.5);
      const double L = map->radiance(PixelIndex{r, c}).luminance();
      EXPECT_GT(light.pdf(kComplete, w), 0.0);  // the complete table leaves nothing out
      if (L < 0.999 * mean) ++dark;
      if (L > 1.001 * mean) {
        EXPECT_GT(light.pdf(kIncomplete, w), 0.0);
      }
    }
  EXPECT_GT(dark, 0u);
  // The compensated table is zero exactly where the luminance is below the mean.
  for (std::size_t i = 0; i < table.tabulated().size(); ++i) {
    const float* v = &map->rgb()[3 * i];
    const double L = Rgb{v[0], v[1], v[2]}.luminance();
    if (L < mean * (1 - 1e-6)) {
      EXPECT_EQ(table.tabulated()[i], 0.0f) << i;
    } else if (L > mean * (1 + 1e-6)) {
      EXPECT_GT(table.tabulated()[i], 0.0f) << i;
    }
  }
}

// Calls that need a complete pdf get the Adaptive table of the same map and options, bit for bit.
TEST(Compensation, CompletePdfsComeFromTheAdaptiveTable) {
  const auto map = smoothMap(64, 32);
  const Rotation r = Rotation::aboutY(0.3);
  const EnvironmentLight compensated(map, {.strategy = EnvironmentSampling::Compensated, .worldFromMap = r});
  const EnvironmentLight adaptive(map, {.strategy = EnvironmentSampling::Adaptive, .worldFromMap = r});
  EXPECT_EQ(compensated.table(kComplete).strategy(), EnvironmentTableStrategy::Adaptive);
  EXPECT_EQ(compensated.table(kComplete).pixelProbabilities(), adaptive.table(kComplete).pixelProbabilities());
  EXPECT_EQ(compensated.tableBytes(), compensated.table(kComplete).bytes() + compensated.table(kIncomplete).bytes());
  expectSameSamples(compensated, kComplete, adaptive, kIncomplete, 4, 1000);
}

TEST(Compensation, ConstantMapFallsBackToTheUncompensatedTable) {
  const auto map = constantMap(16, 8, 3.0f);
  const EnvironmentLight compensated(map, {.strategy = EnvironmentSampling::Compensated});
  const EnvironmentLight adaptive(map, {.strategy = EnvironmentSampling::Adaptive});
  const EnvironmentTable& table = compensated.table(kIncomplete);
  EXPECT_TRUE(table.compensationFellBack());
  EXPECT_TRUE(table.complete());
  EXPECT_FALSE(compensated.emitsNothing());
  // One table serves both kinds of call.
  EXPECT_EQ(&table, &compensated.table(kComplete));
  EXPECT_EQ(compensated.tableBytes(), adaptive.tableBytes());
  EXPECT_EQ(table.pixelProbabilities(), adaptive.table({}).pixelProbabilities());
  EXPECT_NEAR(compensated.pdf(kIncomplete, {0, 0, 1}), 1 / (4 * kPi), 1e-6);
}

// Every table strategy is a light strategy of the same name; Local is the light's alone.
TEST(TableSource, TableStrategiesAreTheLightsButLocal) {
  for (EnvironmentTableStrategy table : kEnvironmentTableStrategies) {
    EXPECT_EQ(tableStrategyOf(samplingOf(table)), table);
    EXPECT_EQ(toString(table), toString(samplingOf(table)));
  }
  EXPECT_EQ(std::size(kEnvironmentSamplings), std::size(kEnvironmentTableStrategies) + 2);
  EXPECT_EQ(tableStrategyOf(EnvironmentSampling::LocalCompensated), std::nullopt);
  EXPECT_EQ(tableStrategyOf(EnvironmentSampling::Local), std::nullopt);
}

// A light asks its table source for what its calls use, and nothing else; lights of one map under
// other rotations and scales share the tables.
TEST(TableSource, LightsGetOnlyTheTablesTheirCallsUse) {
  const auto map = smoothMap(32, 16);
  using Table = EnvironmentTableStrategy;
  std::vector<Table> asked;
  std::map<Table, std::shared_ptr<const EnvironmentTable>> built;
  const EnvironmentTableSource source = [&](Table strategy, const SimplifyOptions& simplify) {
    asked.push_back(strategy);
    auto& table = built[strategy];
    if (!table) table = std::make_shared<const EnvironmentTable>(map, strategy, simplify);
    return table;
  };
  using enum EnvironmentSampling;
  auto tablesFor = [&](EnvironmentSampling strategy, LightPdfs pdfs) {
    asked.clear();
    EnvironmentLight light(map, {.strategy = strategy}, pdfs, source);
    return asked;
  };
  EXPECT_EQ(tablesFor(Compensated, LightPdfs::Incomplete), std::vector{Table::Compensated});
  EXPECT_EQ(tablesFor(Compensated, LightPdfs::Complete), std::vector{Table::Adaptive});
  EXPECT_EQ(tablesFor(Compensated, LightPdfs::Either), (std::vector{Table::Compensated, Table::Adaptive}));
  for (EnvironmentSampling s : {UniformSphere, Uniform, Alias, Adaptive, Hierarchical})
    for (LightPdfs pdfs : {LightPdfs::Complete, LightPdfs::Incomplete, LightPdfs::Either})
      EXPECT_EQ(tablesFor(s, pdfs), std::vector{*tableStrategyOf(s)}) << toString(s);
  for (LightPdfs pdfs : {LightPdfs::Complete, LightPdfs::Incomplete, LightPdfs::Either})
    EXPECT_EQ(tablesFor(Local, pdfs), std::vector{Table::Adaptive});  // the local table is the light's own

  // A light made for incomplete pdfs only cannot answer a call that needs a complete one.
  const EnvironmentLight mis(map, {.strategy = Compensated}, LightPdfs::Incomplete, source);
  EXPECT_THROW((void)mis.sample(kComplete, 0.5f, 0.5f), std::logic_error);
  EXPECT_EQ(mis.tableBytes(), built.at(Table::Compensated)->bytes());

  const EnvironmentLight plain(map, {.strategy = Adaptive}, LightPdfs::Either, source);
  const EnvironmentLight turned(map, {.strategy = Adaptive, .worldFromMap = Rotation::aboutY(1.0), .scale = 2.0f},
                                LightPdfs::Either, source);
  EXPECT_EQ(&plain.table({}), &turned.table({}));

  // The source must give a table of the light's map size and the strategy asked for.
  const EnvironmentTableSource wrong = [&](Table strategy, const SimplifyOptions& simplify) {
    return std::make_shared<const EnvironmentTable>(smoothMap(16, 16), strategy, simplify);
  };
  EXPECT_THROW(EnvironmentLight(map, {}, LightPdfs::Either, wrong), std::invalid_argument);
}

// A local light samples its local table, in the map frame, for calls with a normal, and the
// Adaptive table for calls without one; the normal is turned into the map frame like directions.
TEST(Local, TheNormalChoosesTheLocalTable) {
  const auto map = smoothMap(256, 128);
  const Rotation rotation = Rotation::aboutY(0.7);
  const EnvironmentLight local(map, {.strategy = EnvironmentSampling::Local,
                                     .worldFromMap = rotation,
                                     .local = {.normalRows = 16, .normalColumns = 32, .blockSize = 8}});
  const EnvironmentLight adaptive(map, {.strategy = EnvironmentSampling::Adaptive, .worldFromMap = rotation});
  const LocalEnvironmentTable* table = local.localTable();
  ASSERT_NE(table, nullptr);
  EXPECT_EQ(adaptive.localTable(), nullptr);
  EXPECT_EQ(table->options().normalRows, 16u);
  EXPECT_EQ(local.tableBytes(), adaptive.tableBytes() + table->bytes());
  // Facing the map's bright lobe (smoothMap: around θ = 0.4π, φ = 0.6π), turned into the world.
  const Vec3d n = rotation.apply(LatLongMapping::direction(0.4 * kPi, 0.6 * kPi));
  Pcg32 rng(8);
  uint64_t above = 0, adaptiveAbove = 0;
  for (int i = 0; i < 4000; ++i) {
    const float u0 = i < 2 ? 0.0f : rng.nextFloat(), u1 = i == 1 ? kOneMinusEpsilon : rng.nextFloat();
    for (const LightSampleContext& plain : kLightContexts) {
      const LightSample a = adaptive.sample(plain, u0, u1), b = local.sample(plain, u0, u1);
      ASSERT_EQ(a.direction, b.direction);
      ASSERT_EQ(a.pdf, b.pdf);
      ASSERT_EQ(local.pdf(plain, a.direction), adaptive.pdf(plain, a.direction));
      LightSampleContext context = plain;
      context.normal = n;
      const LightSample s = local.sample(context, u0, u1);
      const LocalEnvironmentTable::Sample t = table->sample(rotation.applyInverse(n), u0, u1);
      ASSERT_EQ(s.direction, rotation.apply(t.direction));
      ASSERT_EQ(s.pdf, t.pdf);
      ASSERT_EQ(local.pdf(context, s.direction), s.pdf);
      ASSERT_EQ(local.eval(s.direction), s.radiance);
      above += dot(s.direction, n) > 0;
      adaptiveAbove += dot(a.direction, n) > 0;
    }
  }
  // The cosine is that of this normal, in the world: few samples below its horizon.
  EXPECT_GT(above, 7400u) << adaptiveAbove;  // 95.8% expected
  EXPECT_LT(adaptiveAbove, 5600u) << above;  // 64.5% expected
  EXPECT_EQ(table->slicesBuilt(), 1u);
}

// A context keeps the normal cell atNormal found, and a call uses it only from that light and for
// that normal: given another normal, or handed to a light with another normal grid, it samples as a
// context that never had one.
TEST(Local, AContextGivenAnotherNormalOrLightFindsItsCellAgain) {
  const auto map = smoothMap(256, 128);
  const EnvironmentLight fine(map, {.strategy = EnvironmentSampling::Local,
                                    .local = {.normalRows = 16, .normalColumns = 32, .blockSize = 8}});
  const EnvironmentLight coarse(map, {.strategy = EnvironmentSampling::Local,
                                      .local = {.normalRows = 4, .normalColumns = 8, .blockSize = 8}});
  const Vec3d from = LatLongMapping::direction(0.4 * kPi, 0.6 * kPi);
  const Vec3d to = LatLongMapping::direction(0.7 * kPi, 0.1 * kPi);
  // What a stale cell would be differs from the one that holds.
  ASSERT_NE(fine.localTable()->sliceOf(from), fine.localTable()->sliceOf(to));
  ASSERT_GE(fine.localTable()->sliceOf(from), coarse.localTable()->slices());

  const LightSampleContext found = fine.atNormal({}, from);
  LightSampleContext moved = found;
  moved.normal = to;
  expectSameSamples(fine, moved, fine, {.normal = to}, 31, 2000);
  expectSameSamples(coarse, found, coarse, {.normal = from}, 32, 2000);
}

// A compensated local light's per-normal tables are incomplete: calls that need a complete pdf get
// the Adaptive table, normal or not; the others its compensated local table.
TEST(Local, CompensatedLocalGivesCompletePdfsFromTheAdaptiveTable) {
  const auto map = smoothMap(64, 32);
  const EnvironmentLight light(map, {.strategy = EnvironmentSampling::LocalCompensated,
                                     .local = {.normalRows = 4, .normalColumns = 8}});
  const EnvironmentLight adaptive(map, {.strategy = EnvironmentSampling::Adaptive});
  ASSERT_TRUE(light.localTable() && light.localTable()->compensated());
  const Vec3d n = normalize(Vec3d{0.3, 0.8, 0.2});
  const LightSampleContext complete = light.atNormal(kComplete, n), incomplete = light.atNormal(kIncomplete, n);
  for (float u0 : {0.0f, 0.3f, 0.7f, kOneMinusEpsilon})
    for (float u1 : {0.0f, 0.5f, kOneMinusEpsilon}) {
      const LightSample c = light.sample(complete, u0, u1), a = adaptive.sample({}, u0, u1);
      EXPECT_EQ(c.direction, a.direction);
      EXPECT_EQ(c.pdf, a.pdf);
      const LightSample i = light.sample(incomplete, u0, u1);
      EXPECT_EQ(i.pdf, light.localTable()->pdf(n, i.direction));
      EXPECT_EQ(light.pdf(incomplete, i.direction), i.pdf);
    }
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
      const CompressionQuality q = compareCellProbabilities(exact, light.table({}).pixelProbabilities());
      EXPECT_EQ(q.unreachableMass, 0.0) << what << " " << toString(strategy) << " epsilon " << epsilon;
    }
  // The pdf the renderer sees, at every lit pixel's centre.
  const EnvironmentLight adaptive(map, {.strategy = EnvironmentSampling::Adaptive});
  std::size_t dark = 0;
  for (uint32_t r = 0; r < map->height(); ++r)
    for (uint32_t c = 0; c < map->width(); ++c)
      if (exact[std::size_t{r} * map->width() + c] > 0 &&
          !(adaptive.pdf({}, map->mapping().directionInPixel({r, c}, 0.5, 0.5)) > 0))
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
    const EnvironmentTable uniform(map, EnvironmentTableStrategy::Uniform, {});
    std::vector<double> exact(uniform.tabulated().begin(), uniform.tabulated().end());
    double total = 0;
    for (double v : exact) total += v;
    for (double& v : exact) v /= total;
    const CompressionQuality q = compareCellProbabilities(exact, uniform.pixelProbabilities());
    std::cout << name << ": uniform table divergence " << q.chi2Divergence << "\n";
    EXPECT_LT(q.chi2Divergence, kUniformTableDivergenceBound) << name;
  }
}

// The quality bar of the adaptive table: on each real map the default one is at least 10×
// smaller than the uniform one, for a χ²-divergence of at most 0.1.
TEST(Quality, AdaptiveTablesOfTheRealMapsAreSmallAndAccurate) {
  ACDF_SKIP_WITHOUT_SHARED_ENVMAPS();
  for (const char* name : kSharedEnvmaps) {
    const auto map = std::make_shared<const EnvironmentMap>(EnvironmentMap::load(sharedEnvmap(name)));
    const EnvironmentLight uniform(map, {.strategy = EnvironmentSampling::Uniform});
    const EnvironmentLight adaptive(map, {.strategy = EnvironmentSampling::Adaptive});
    const EnvironmentTable& table = adaptive.table({});
    std::vector<double> exact(table.tabulated().begin(), table.tabulated().end());
    double total = 0;
    for (double v : exact) total += v;
    for (double& v : exact) v /= total;
    const CompressionQuality q = compareCellProbabilities(exact, table.pixelProbabilities());
    const double compression = double(uniform.tableBytes()) / double(adaptive.tableBytes());
    std::cout << name << ": compression " << compression << "x, chi2 divergence " << q.chi2Divergence
              << ", max weight ratio " << q.maxWeightRatio << "\n";
    EXPECT_GE(compression, 10.0) << name;
    EXPECT_LE(q.chi2Divergence, 0.1) << name;
    EXPECT_EQ(q.unreachableMass, 0.0) << name;
  }
}

}  // namespace
