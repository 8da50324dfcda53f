// Portals (EnvironmentLight::sample): every sample's pdf is the mixture's density at its direction,
// the mixture's expectations are the integrals they estimate (z-tests on 10⁶ samples), a sun seen
// through a window takes the portal samples its light's share of the window gives it, a point
// behind every portal or a call without a position samples as a light without portals, the
// portals found for a point serve no other point or light, more portals than a context keeps
// sample as their union, and bad portals are refused.

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
#include "acdf/test_support/chi_square_registry.h"
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
        // The same point reached in place from another vertex (moveTo, a path tracer's): nothing
        // the other vertex found (its portals, its normal cell) may stay.
        LightSampleContext moved{.allowIncompletePdf = incomplete};
        light.moveTo(moved, position + Vec3d{0.9, -0.4, 0.7}, normalize({-0.6, 0.2, 0.5}));
        light.moveTo(moved, position, normalize({0.2, 1, -0.3}));
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
          // The same with the portals' views found once for the point (atPosition).
          const LightSampleContext once = light.atPosition(context, position);
          ASSERT_EQ(light.sample(once, u0, u1).pdf, s.pdf);
          ASSERT_EQ(light.pdf(once, s.direction), s.pdf);
          const LightSample m = light.sample(moved, u0, u1);
          ASSERT_EQ(m.direction, s.direction);
          ASSERT_EQ(m.pdf, s.pdf);
          ASSERT_EQ(light.evalWithPdf(moved, s.direction).pdf, s.pdf);
          ASSERT_EQ(e.radiance.r, s.radiance.r);
          // u0 below the portals' share draws through one of them (every point here faces one).
          bool through = false;
          for (const Portal& p : {kWindow, kSideWindow})
            through = through || SphericalRectangle(position, p.corner, p.edgeU, p.edgeV).pdf(s.direction) > 0;
          if (u0 < EnvironmentLight::portalShare(context)) {
            ASSERT_TRUE(through) << u0 << ", " << u1;
          }
        }
      }
  }
}

TEST(Portals, ExpectationsEqualTheIntegralsTheyEstimate) {
  // E[g(ω) / p(ω)] = ∫ g over the support of p, for g = 1 (the whole sphere: 4π), g = the
  // indicator of a window (its solid angle), g = L's luminance (the map's power) and g = the
  // window's indicator times cos θ to a normal facing it (the irradiance of a unit sky through the
  // window, Lambert's formula), at 10⁶ samples. Where an incomplete pdf is allowed (MIS), every
  // sample goes through a portal: the support is the two windows, g = 1 gives their solid angles
  // and the map's power is not checked. z-tests at alpha 0.01, Sidak-corrected over the 4 × 2 + 3 × 2
  // tests.
  const EnvironmentLight light = lightWith(EnvironmentSampling::Adaptive, {kWindow, kSideWindow});
  const std::vector<float> power = light.map().pixelPower();
  double mapPower = 0;
  for (float p : power) mapPower += p;
  const double alpha = sidakAlpha(0.01, 14);
  // The two-sided normal quantile of alpha, by bisection on erfc.
  double lo = 0, hi = 10;
  for (int i = 0; i < 100; ++i) ((std::erfc((lo + hi) / 2 / std::sqrt(2.0)) > alpha) ? lo : hi) = (lo + hi) / 2;
  const double z = lo;
  struct Case {
    bool incomplete;
    Vec3d position;
  };
  for (const auto& [incomplete, position] :
       {Case{false, kInside[0]}, Case{false, kInside[2]}, Case{true, kInside[0]}, Case{true, kInside[2]}}) {
    SCOPED_TRACE(incomplete ? "incomplete" : "complete");
    const LightSampleContext context{.allowIncompletePdf = incomplete, .position = position};
    const SphericalRectangle window(position, kWindow.corner, kWindow.edgeU, kWindow.edgeV);
    const SphericalRectangle side(position, kSideWindow.corner, kSideWindow.edgeU, kSideWindow.edgeV);
    Pcg32 rng(19);
    const int n = 1'000'000;
    const Vec3d facing = normalize({0.1, -0.2, 1.0});
    double sum[4] = {}, squares[4] = {};
    for (int k = 0; k < n; ++k) {
      const LightSample s = light.sample(context, rng.nextFloat(), rng.nextFloat());
      const double through = window.pdf(s.direction) > 0 ? 1.0 : 0.0;
      const double g[4] = {1.0, through, 0.2126 * s.radiance.r + 0.7152 * s.radiance.g + 0.0722 * s.radiance.b,
                           through * std::max(0.0, dot(facing, s.direction))};
      for (int i = 0; i < 4; ++i) {
        sum[i] += g[i] / s.pdf;
        squares[i] += (g[i] / s.pdf) * (g[i] / s.pdf);
      }
    }
    // Lambert: ∫ cos θ dω over a polygon above the tangent plane = ½ Σ_edges γ_e n · (v_e × v_e+1)
    // / |v_e × v_e+1|, the corners' unit directions v in order, γ_e the angle between them.
    const Vec3d corners[4] = {kWindow.corner, kWindow.corner + kWindow.edgeU, kWindow.corner + kWindow.edgeU + kWindow.edgeV,
                              kWindow.corner + kWindow.edgeV};
    double irradiance = 0;
    for (int e = 0; e < 4; ++e) {
      const Vec3d v0 = normalize(corners[e] - position), v1 = normalize(corners[(e + 1) % 4] - position);
      ASSERT_GT(dot(facing, v0), 0.0) << "the window is above the tangent plane";
      const Vec3d c = cross(v0, v1);
      irradiance += 0.5 * std::acos(std::clamp(dot(v0, v1), -1.0, 1.0)) * dot(facing, c) / length(c);
    }
    const double expected[4] = {incomplete ? window.solidAngle() + side.solidAngle() : 4.0 * std::numbers::pi,
                                window.solidAngle(), mapPower, std::abs(irradiance)};
    const char* what[4] = {incomplete ? "the windows' solid angles" : "4 pi", "the window's solid angle",
                           "the map's power", "a unit sky's irradiance"};
    for (int i = 0; i < 4; ++i) {
      if (incomplete && i == 2) continue;
      const double mean = sum[i] / n, se = std::sqrt((squares[i] / n - mean * mean) / n);
      EXPECT_LT(std::abs(mean - expected[i]), z * se) << what[i] << ": " << mean << " against " << expected[i];
    }
  }
}

// The sun of skyWithSun() seen through the window from a point in the room: portal samples land
// in the sun's pixel about as often as its share of the light through the window (nearly all of
// it here), 2·10⁵ of them.
TEST(Portals, ASunThroughTheWindowTakesItsShareOfThePortalSamples) {
  const EnvironmentLight light = lightWith(EnvironmentSampling::Adaptive, {kWindow});
  const PixelIndex sun{12, 29};
  // A point the sun shines on through the window: back from the window's middle along the sun's
  // direction (into the room).
  const Vec3d toSun = light.options().worldFromMap.apply(light.map().mapping().directionInPixel(sun, 0.5, 0.5));
  const Vec3d middle = kWindow.corner + kWindow.edgeU * 0.5 + kWindow.edgeV * 0.5;
  ASSERT_GT(toSun.z, 0.3);
  const Vec3d position = middle - toSun * (1.5 / toSun.z);
  ASSERT_GT(SphericalRectangle(position, kWindow.corner, kWindow.edgeU, kWindow.edgeV).pdf(toSun), 0.0);
  const LightSampleContext context = light.atPosition({}, position);
  // The sun's share of the light through the window: its pixel's power over ∫ luminance dω
  // through the window (directions uniform in its solid angle, 2·10⁵ of them: 1 % error).
  const SphericalRectangle window(position, kWindow.corner, kWindow.edgeU, kWindow.edgeV);
  const double sunPower = light.map().radiance(sun).luminance() * light.map().mapping().pixelSolidAngle(sun.row);
  double throughWindow = 0;
  Pcg32 uniform(43);
  for (int k = 0; k < 200'000; ++k)
    throughWindow += light.eval(window.sample(uniform.nextDouble(), uniform.nextDouble()).direction).luminance() *
                     window.solidAngle() / 200'000;
  const double share = sunPower / throughWindow;
  ASSERT_GT(share, 0.5);
  Pcg32 rng(41);
  const int n = 200'000;
  int hits = 0;
  for (int k = 0; k < n; ++k) {
    const float u0 = static_cast<float>(rng.nextFloat() * EnvironmentLight::portalShare(context));
    const LightSample s = light.sample(context, u0, rng.nextFloat());
    hits += light.map().mapping().pixelOf(light.options().worldFromMap.applyInverse(s.direction)) == sun;
  }
  // The table's cells do not follow the pixel's edges: the cells the sun's edges cut give some of
  // its samples to the sky beside it (PortalTable's fine cells are a sixth of this map's pixels).
  // Directions uniform in the window's solid angle would hit it 1 time in 20.
  EXPECT_GT(static_cast<double>(hits) / n, 0.8 * share);
  EXPECT_LE(static_cast<double>(hits) / n, share);
}

TEST(Portals, AWindowHoldsTheDirectionsThatCrossThePortalFromThere) {
  const EnvironmentLight light = lightWith(EnvironmentSampling::Compensated, {kWindow});
  const PortalTable& table = light.portalTable(0);
  EXPECT_FALSE(table.windowFrom(kBehindBoth));
  Pcg32 rng(11);
  int crossing = 0;
  for (const Vec3d& from : kInside) {
    const std::optional<WindowedTable2D::Window> window = table.windowFrom(from);
    ASSERT_TRUE(window);
    for (int k = 0; k < 20000; ++k) {
      const Vec3d w = sampleUniformSphere(rng.nextDouble(), rng.nextDouble());
      // The ray from `from` along w meets the window's rectangle.
      const Vec3d n = cross(kWindow.edgeU, kWindow.edgeV);
      const double t = dot(kWindow.corner - from, n) / dot(w, n);
      const Vec3d q = from + w * t - kWindow.corner;
      const double s = dot(q, kWindow.edgeU) / dot(kWindow.edgeU, kWindow.edgeU);
      const double r = dot(q, kWindow.edgeV) / dot(kWindow.edgeV, kWindow.edgeV);
      const bool crosses = t > 0 && s >= 0 && s <= 1 && r >= 0 && r <= 1;
      crossing += crosses;
      ASSERT_EQ(crosses, table.densityThrough(*window, w) > 0) << "from point " << &from - kInside << ", k " << k;
    }
  }
  EXPECT_GT(crossing, 500);
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

TEST(Portals, AContextMovedOrGivenToAnotherLightFindsItsPortalsAgain) {
  const EnvironmentLight both = lightWith(EnvironmentSampling::Adaptive, {kWindow, kSideWindow});
  const EnvironmentLight windowOnly = lightWith(EnvironmentSampling::Adaptive, {kWindow});
  const Vec3d from = kInside[0], to = kInside[1];
  // What a stale context would keep differs from what holds: the portals' light from the two
  // points, and the two lights' from one point.
  auto power = [&both](const Vec3d& o, std::size_t portal) { return both.portalTable(portal).viewFrom(o).power; };
  ASSERT_GT(std::abs(power(from, 0) - power(to, 0)), 0.01 * power(to, 0));
  ASSERT_GT(power(from, 1), 0.01 * power(from, 0));

  const LightSampleContext found = both.atPosition({}, from);
  LightSampleContext moved = found;
  moved.position = to;
  expectSameSamples(both, moved, both, {.position = to}, 29, 2000);
  expectSameSamples(windowOnly, found, windowOnly, {.position = from}, 30, 2000);
}

// The window cut into 3 × 4 portals: more than a context keeps (PortalsSeen::kCapacity), so the
// calls find the last ones' views themselves.
std::vector<Portal> windowInPieces() {
  std::vector<Portal> pieces;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      pieces.push_back({kWindow.corner + kWindow.edgeU * (i / 3.0) + kWindow.edgeV * (j / 4.0),
                        kWindow.edgeU * (1.0 / 3.0), kWindow.edgeV * (1.0 / 4.0)});
  return pieces;
}

// 10⁵ portal samples (u0 below the portals' share) from each point binned by the piece they pass
// through, whose probability is its share of the light through the pieces; the density everywhere
// that of the whole window.
ACDF_CHI_SQUARE_TEST(Portals, MorePortalsThanAContextKeepsSampleAsTheirUnion, 3) {
  const std::vector<Portal> pieces = windowInPieces();
  static_assert(PortalsSeen::kCapacity < 12);
  const EnvironmentLight cut = lightWith(EnvironmentSampling::Adaptive, pieces);
  const EnvironmentLight whole = lightWith(EnvironmentSampling::Adaptive, {kWindow});
  for (const Vec3d& position : kInside) {
    SCOPED_TRACE(position.x);
    const LightSampleContext context = cut.atPosition({}, position), plain{.position = position};
    std::vector<double> expected, observed(pieces.size(), 0.0);
    std::vector<SphericalRectangle> seen;
    double total = 0;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      seen.emplace_back(position, pieces[i].corner, pieces[i].edgeU, pieces[i].edgeV);
      total += cut.portalTable(i).viewFrom(position).power;
    }
    const int n = 100'000;
    for (std::size_t i = 0; i < pieces.size(); ++i)
      expected.push_back(n * cut.portalTable(i).viewFrom(position).power / total);
    Pcg32 rng(31);
    for (int k = 0; k < n; ++k) {
      const float u0 = static_cast<float>(rng.nextFloat() * EnvironmentLight::portalShare(context)),
                  u1 = rng.nextFloat();
      const LightSample s = cut.sample(context, u0, u1);
      ASSERT_EQ(cut.pdf(context, s.direction), s.pdf);
      const LightSample fresh = cut.sample(plain, u0, u1);
      ASSERT_EQ(fresh.direction, s.direction);
      ASSERT_EQ(fresh.pdf, s.pdf);
      std::size_t piece = 0;
      while (piece < seen.size() && !(seen[piece].pdf(s.direction) > 0)) ++piece;
      ASSERT_LT(piece, seen.size());
      observed[piece] += 1;
      // A direction through the window, away from the pieces' shared edges: the whole's density.
      const Vec3d w = SphericalRectangle(position, kWindow.corner, kWindow.edgeU, kWindow.edgeV)
                          .sample(rng.nextFloat(), rng.nextFloat())
                          .direction;
      ASSERT_NEAR(cut.pdf(context, w), whole.pdf(plain, w), 1e-9 * whole.pdf(plain, w));
    }
    const ChiSquareResult result = chiSquareTest(observed, expected);
    EXPECT_GE(result.pvalue, test_support::chiSquareTestLevel())
        << "chi2 " << result.statistic << " dof " << result.dof;
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
