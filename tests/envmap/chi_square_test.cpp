// Chi-square goodness of fit of every sampling strategy against its own pdf, on generated maps
// (one lit pixel, constant, 3 × 2, sun and sky at 4096 × 2048) and the real maps of the shared
// test data (local sampling at one normal). Each test also checks every sample (unit direction, finite positive pdf
// equal to pdf(ω), the extreme variates included) and that the pdf integrates to 1 over the sphere.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <string>

#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/light_chi_square.h"
#include "acdf/envmap/sun_sky.h"
#include "acdf/test_support/chi_square_registry.h"
#include "envmap_test_util.h"

namespace {

using namespace acdf;
using namespace acdf::envmaptest;
using test_support::chiSquareTestLevel;

// Every strategy on the generated maps, the table strategies on the real ones (uniform-sphere
// sampling ignores the map); compensated with its own table (the default of
// LightChiSquareOptions: its complete one is the adaptive table).
constexpr auto& kAllStrategies = kEnvironmentSamplings;
const char* const kGeneratedMaps[] = {"one_lit_pixel_100x10", "constant_100x100", "tiny_3x2", "sun_and_sky_4096x2048"};

// A test-name part: "uniform-sphere" → "uniform_sphere".
std::string identifier(EnvironmentSampling strategy) {
  std::string name(toString(strategy));
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

std::shared_ptr<const EnvironmentMap> generatedMap(const std::string& name) {
  static std::map<std::string, std::shared_ptr<const EnvironmentMap>> cache;
  auto& map = cache[name];
  if (map) return map;
  if (name == "one_lit_pixel_100x10") map = onePixelMap(100, 10, 3, 71, 5.0f);
  if (name == "constant_100x100") map = constantMap(100, 100);
  if (name == "tiny_3x2") map = makeMap(3, 2, [](uint32_t r, uint32_t c) { return Rgb{1.0f + r + 2 * c, 1, 0.5f}; });
  if (name == "sun_and_sky_4096x2048")
    map = std::make_shared<const EnvironmentMap>(4096, 2048, sunSkyImage(4096, 2048, sunSkyPreset("noon")).pixels);
  return map;
}

void expectPasses(const EnvironmentLight& light, const std::string& what) {
  LightChiSquareOptions options;
  options.alpha = chiSquareTestLevel();
  // Local sampling for a normal between the horizon and the zenith (without one it would be the
  // Adaptive table's); local_table_test.cpp tests more normals.
  if (!tableStrategyOf(light.options().strategy)) options.context.normal = normalize(Vec3d{0.5, 0.6, -0.3});
  const SphereChiSquareReport report = lightChiSquareTest(light, options);
  std::cout << what << ": " << report.summary() << "\n";
  EXPECT_TRUE(report.passed()) << what << ": " << report.summary();
  EXPECT_NEAR(report.pdfIntegral, 1.0, 1e-4) << what;
}

class Generated : public ::testing::TestWithParam<std::tuple<const char*, EnvironmentSampling>> {};

ACDF_CHI_SQUARE_TEST_P(Generated, SamplerMatchesItsPdf, 1) {
  const auto [name, strategy] = GetParam();
  const EnvironmentLight light(generatedMap(name), {.strategy = strategy});
  expectPasses(light, std::string(name) + " " + std::string(toString(strategy)));
}

INSTANTIATE_TEST_SUITE_P(Maps, Generated,
                         ::testing::Combine(::testing::ValuesIn(kGeneratedMaps), ::testing::ValuesIn(kAllStrategies)),
                         [](const auto& info) {
                           return std::string(std::get<0>(info.param)) + "_" + identifier(std::get<1>(info.param));
                         });

class Shared : public ::testing::TestWithParam<std::tuple<const char*, EnvironmentSampling>> {};

ACDF_CHI_SQUARE_TEST_P(Shared, SamplerMatchesItsPdf, 1) {
  ACDF_SKIP_WITHOUT_SHARED_ENVMAPS();
  const auto [name, strategy] = GetParam();
  const auto map = std::make_shared<const EnvironmentMap>(EnvironmentMap::load(sharedEnvmap(name)));
  const EnvironmentLight light(map, {.strategy = strategy});
  expectPasses(light, std::string(name) + " " + std::string(toString(strategy)));
}

INSTANTIATE_TEST_SUITE_P(RealMaps, Shared,
                         ::testing::Combine(::testing::ValuesIn(kSharedEnvmaps), ::testing::ValuesIn(kTableStrategies)),
                         [](const auto& info) {
                           std::string name = std::get<0>(info.param);
                           name = name.substr(0, name.find('_'));
                           return name + "_" + identifier(std::get<1>(info.param));
                         });

// The test can fail: a light whose sample() and pdf() disagree (its pdf is another map's) is
// rejected.
ACDF_CHI_SQUARE_TEST(ChiSquareHarness, RejectsASamplerThatDoesNotMatchItsPdf, 1) {
  const auto skewed = makeMap(64, 32, [](uint32_t r, uint32_t c) { return Rgb{1.0f + r + c, 1, 1}; });
  const EnvironmentLight sampled(skewed, {.strategy = EnvironmentSampling::Uniform});
  const EnvironmentLight other(constantMap(64, 32), {.strategy = EnvironmentSampling::Uniform});
  SphereChiSquareOptions o;
  o.alpha = chiSquareTestLevel();
  o.samples = 200'000;
  o.thetaBins = 32;
  o.phiBins = 64;
  o.subPoints = 1;
  const SphereChiSquareReport report = sphereChiSquareTest(
      [&](float u0, float u1) {
        const LightSample s = sampled.sample({}, u0, u1);
        return DirectionSample{LatLongMapping::toZUp(s.direction), other.pdf({}, s.direction)};
      },
      [&](const Vec3d& z) { return other.pdf({}, LatLongMapping::fromZUp(z)); }, o);
  EXPECT_FALSE(report.chiSquarePassed()) << report.summary();
}

}  // namespace
