// Portals (EnvironmentLight::sample): every sample's pdf is the mixture's density at its direction,
// the mixture's expectations are the integrals they estimate (z-tests on 10⁶ samples), a point
// behind every portal or a call without a position samples as a light without portals, and bad
// portals are refused.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "acdf/envmap/environment_light.h"
#include "acdf/sampling/chi_square.h"
#include "acdf/sampling/option_error.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/sample.h"
#include "acdf/sampling/spherical_rectangle.h"
#include "envmap_test_util.h"

namespace {

using namespace acdf;
using namespace acdf::envmaptest;

// A room x, z in [-2, 2], y in [0, 2.6]: a window in the wall z = 2 and one in the wall x = -2,
// each passing light into the room (edgeU × edgeV points inwards).
const Portal kWindow{{-0.7, 0.9, 2.0}, {0, 1.1, 0}, {1.4, 0, 0}};
const Portal kSideWindow{{-2.0, 0.5, -1.0}, {0, 1.0, 0}, {0, 0, 1.5}};
const Vec3d kInside[] = {{0.1, 1.0, -0.5}, {1.5, 0.3, 1.5}, {-1.9, 2.0, 0.0}};
const Vec3d kBehindBoth{3.0, 1.0, 3.0};

// A smooth sky with a sun of one pixel: what the portals' uniform density alone would miss.
std::shared_ptr<const EnvironmentMap> skyWithSun() {
  return makeMap(64, 32, [](uint32_t row, uint32_t column) {
    const float sky = 0.5f + 0.02f * row + 0.01f * column;
    return row == 12 && column == 29 ? Rgb{3000, 2800, 2500} : Rgb{0.6f * sky, 0.8f * sky, sky};
  });
}

EnvironmentLight lightWith(EnvironmentSampling strategy, std::vector<Portal> portals) {
  EnvironmentLightOptions o;
  o.strategy = strategy;
  o.worldFromMap = Rotation::aboutY(0.7);
  o.portals = std::move(portals);
  return EnvironmentLight(skyWithSun(), o);
}

TEST(Portals, EverySampleCarriesTheMixturesDensityAtItsDirection) {
  const float extremes[] = {0.0f, 0.25f, 0.4999999f, 0.5f, kOneMinusEpsilon};
  for (EnvironmentSampling strategy : {EnvironmentSampling::Adaptive, EnvironmentSampling::Compensated,
                                       EnvironmentSampling::Local, EnvironmentSampling::UniformSphere}) {
    const EnvironmentLight light = lightWith(strategy, {kWindow, kSideWindow});
    for (const Vec3d& position : kInside)
      for (bool incomplete : {false, true}) {
        const LightSampleContext context =
            light.atNormal({.allowIncompletePdf = incomplete, .position = position}, normalize({0.2, 1, -0.3}));
        SCOPED_TRACE(std::string(toString(strategy)) + (incomplete ? ", incomplete" : ", complete"));
        Pcg32 rng(3);
        std::vector<std::array<float, 2>> variates;
        for (float a : extremes)
          for (float b : extremes) variates.push_back({a, b});
        for (int k = 0; k < 5000; ++k) variates.push_back({rng.nextFloat(), rng.nextFloat()});
        for (const auto& [u0, u1] : variates) {
          const LightSample s = light.sample(context, u0, u1);
          ASSERT_GT(s.pdf, 0.0);
          ASSERT_TRUE(std::isfinite(s.pdf));
          ASSERT_NEAR(length(s.direction), 1.0, 1e-12);
          ASSERT_EQ(light.pdf(context, s.direction), s.pdf) << u0 << ", " << u1;
          const RadianceAndPdf e = light.evalWithPdf(context, s.direction);
          ASSERT_EQ(e.pdf, s.pdf);
          // The same with the portals' solid angle found once for the point (atPosition).
          const LightSampleContext once = light.atPosition(context, position);
          ASSERT_EQ(light.sample(once, u0, u1).pdf, s.pdf);
          ASSERT_EQ(light.pdf(once, s.direction), s.pdf);
          ASSERT_EQ(e.radiance.r, s.radiance.r);
          // u0 below the portals' share draws through one of them (every point here faces one).
          bool through = false;
          for (const Portal& p : {kWindow, kSideWindow})
            through = through || SphericalRectangle(position, p.corner, p.edgeU, p.edgeV).pdf(s.direction) > 0;
          if (u0 < EnvironmentLight::kPortalShare) ASSERT_TRUE(through) << u0 << ", " << u1;
        }
      }
  }
}

TEST(Portals, ExpectationsEqualTheIntegralsTheyEstimate) {
  // E[g(ω) / p(ω)] = ∫ g over the support of p, for g = 1 (the whole sphere: 4π), g = the
  // indicator of a window (its solid angle) and g = L's luminance (the map's power), at 10⁶
  // samples: z-tests at alpha 0.01, Sidak-corrected over the 3 × 2 tests.
  const EnvironmentLight light = lightWith(EnvironmentSampling::Adaptive, {kWindow, kSideWindow});
  const std::vector<float> power = light.map().pixelPower();
  double mapPower = 0;
  for (float p : power) mapPower += p;
  const double alpha = sidakAlpha(0.01, 6);
  // The two-sided normal quantile of alpha, by bisection on erfc.
  double lo = 0, hi = 10;
  for (int i = 0; i < 100; ++i) ((std::erfc((lo + hi) / 2 / std::sqrt(2.0)) > alpha) ? lo : hi) = (lo + hi) / 2;
  const double z = lo;
  for (const Vec3d& position : {kInside[0], kInside[2]}) {
    const LightSampleContext context{.allowIncompletePdf = false, .position = position};
    const SphericalRectangle window(position, kWindow.corner, kWindow.edgeU, kWindow.edgeV);
    Pcg32 rng(19);
    const int n = 1'000'000;
    double sum[3] = {}, squares[3] = {};
    for (int k = 0; k < n; ++k) {
      const LightSample s = light.sample(context, rng.nextFloat(), rng.nextFloat());
      const double g[3] = {1.0, window.pdf(s.direction) > 0 ? 1.0 : 0.0,
                           0.2126 * s.radiance.r + 0.7152 * s.radiance.g + 0.0722 * s.radiance.b};
      for (int i = 0; i < 3; ++i) {
        sum[i] += g[i] / s.pdf;
        squares[i] += (g[i] / s.pdf) * (g[i] / s.pdf);
      }
    }
    const double expected[3] = {4.0 * std::numbers::pi, window.solidAngle(), mapPower};
    const char* what[3] = {"4 pi", "the window's solid angle", "the map's power"};
    for (int i = 0; i < 3; ++i) {
      const double mean = sum[i] / n, se = std::sqrt((squares[i] / n - mean * mean) / n);
      EXPECT_LT(std::abs(mean - expected[i]), z * se) << what[i] << ": " << mean << " against " << expected[i];
    }
  }
}

TEST(Portals, BehindEveryPortalOrWithoutAPositionTheLightIsUnchanged) {
  const EnvironmentLight plain = lightWith(EnvironmentSampling::Compensated, {});
  const EnvironmentLight portals = lightWith(EnvironmentSampling::Compensated, {kWindow});
  Pcg32 rng(5);
  for (int k = 0; k < 2000; ++k) {
    const float u0 = rng.nextFloat(), u1 = rng.nextFloat();
    for (const LightSampleContext& context :
         {LightSampleContext{.allowIncompletePdf = true, .position = kBehindBoth},
          LightSampleContext{.allowIncompletePdf = true}}) {
      const LightSample a = plain.sample(context, u0, u1), b = portals.sample(context, u0, u1);
      ASSERT_EQ(a.direction.x, b.direction.x);
      ASSERT_EQ(a.pdf, b.pdf);
      ASSERT_EQ(plain.pdf(context, a.direction), portals.pdf(context, a.direction));
    }
  }
}

TEST(Portals, BadPortalsAreRefusedNamingThem) {
  const Portal zeroEdge{{0, 0, 0}, {0, 0, 0}, {1, 0, 0}};
  const Portal slanted{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  const Portal infinite{{0, 0, 0}, {INFINITY, 0, 0}, {0, 1, 0}};
  EXPECT_EQ(portalProblem(kWindow), std::nullopt);
  EXPECT_EQ(portalProblem(zeroEdge), "its edges must not be zero");
  EXPECT_EQ(portalProblem(slanted), "edge_u and edge_v must be perpendicular");
  EXPECT_EQ(portalProblem(infinite), "its corner and edges must be finite");
  EnvironmentLightOptions o;
  o.portals = {kWindow, slanted};
  try {
    validate(o);
    FAIL() << "a slanted portal was accepted";
  } catch (const OptionError& e) {
    EXPECT_EQ(e.option(), "portals");
    EXPECT_EQ(e.problem(), "[1]: edge_u and edge_v must be perpendicular");
  }
  EXPECT_THROW(EnvironmentLight(skyWithSun(), o), OptionError);
}

}  // namespace
