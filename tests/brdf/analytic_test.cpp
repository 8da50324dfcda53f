// AnalyticBrdf: the closed form at the specular peak, reciprocity, energy (directional albedo by
// quadrature over the half vector), the MERL table it builds, and the preset names.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/coordinates.h"
#include "acdf/brdf/merl.h"
#include "acdf/brdf/merl_tabulation.h"
#include "acdf/brdf/nbrdf.h"

namespace {

using namespace acdf;
constexpr double kPi = std::numbers::pi;
constexpr std::size_t kN = MerlBrdf::kCells;

// ∫ f(ωi, ωo) cos θo dωo for ωi at polar angle thetaI, channel c: over the half vector h
// (dωo = 4 |ωi·h| dωh), midpoint rule in √θh (dense at the peak) and φh.
double albedo(const AnalyticBrdf& brdf, double thetaI, int c) {
  const Vec3d wi = sphericalDirection(thetaI, 0.0);
  constexpr int kS = 1500, kPhi = 600;
  double sum = 0;
  for (int a = 0; a < kS; ++a) {
    const double s = (a + 0.5) / kS;
    const double thetaH = s * s * (kPi / 2);
    const double dTheta = s * kPi / kS;  // dθh = π s ds
    for (int b = 0; b < kPhi; ++b) {
      const double phiH = (b + 0.5) / kPhi * 2 * kPi;
      const Vec3d h = sphericalDirection(thetaH, phiH);
      const double cosD = wi.x * h.x + wi.y * h.y + wi.z * h.z;
      if (cosD <= 0) continue;
      const Vec3d wo{2 * cosD * h.x - wi.x, 2 * cosD * h.y - wi.y, 2 * cosD * h.z - wi.z};
      if (wo.z <= 0) continue;
      const HalfDiffAngles a2 = toHalfDiff(wo, wi);
      const double f = brdf.closedForm(a2.thetaHalf, a2.thetaDiff, a2.phiDiff)[c];
      sum += f * wo.z * 4 * cosD * std::sin(thetaH) * dTheta * (2 * kPi / kPhi);
    }
  }
  return sum;
}

TEST(AnalyticBrdf, ClosedFormAtTheSpecularPeak) {
  const AnalyticBrdf gold = AnalyticBrdf::preset("gold");
  for (double td : {0.0, 0.4, 1.0}) {
    // θh = 0: ωi = ωo mirrored about the normal, both at θd; D(0) = 1/(π α²).
    const double a = gold.alpha(), c = std::cos(td);
    const double g1 = 2 / (1 + std::sqrt(1 + a * a * std::tan(td) * std::tan(td)));
    const double m = 1 - c;
    for (int ch = 0; ch < 3; ++ch) {
      const double fresnel = gold.f0()[ch] + (1 - gold.f0()[ch]) * std::pow(m, 5);
      const double expected = fresnel / (kPi * a * a) * g1 * g1 / (4 * c * c);
      EXPECT_NEAR(gold.closedForm(0.0, td, 0.7)[ch], expected, 1e-12 * expected) << td << " " << ch;
    }
  }
  // Below the horizon: 0.
  EXPECT_EQ(gold.closedForm(1.0, 1.0, 0.0)[0], 0.0);
}

TEST(AnalyticBrdf, Reciprocal) {
  for (const std::string& name : AnalyticBrdf::presetNames()) {
    const AnalyticBrdf brdf = AnalyticBrdf::preset(name);
    for (double th : {0.05, 0.3, 0.6})
      for (double td : {0.1, 0.5, 0.8})
        for (double pd : {0.0, 0.9, 2.0}) {
          const auto f = brdf.closedForm(th, td, pd), g = brdf.closedForm(th, td, pd + kPi);
          for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], g[c], 1e-12 * (1 + f[c])) << name;
        }
  }
}

// A white conductor (F0 = 1) loses energy only to shadowing and the horizon: albedo just below 1
// at normal incidence (0.9719 for α = 0.15 by an independent 1D quadrature of D·G1 over θh:
// GGX's tails are long), never above 1; the presets stay below 1 too.
TEST(AnalyticBrdf, EnergyConserving) {
  const AnalyticBrdf white = AnalyticBrdf::conductor(AnalyticBrdf::preset("gold").alpha(), {1.0, 1.0, 1.0});
  const double normal = albedo(white, 0.0, 0);
  std::cout << "[ albedo ] white GGX conductor, alpha " << white.alpha() << ", normal incidence: " << normal << "\n";
  EXPECT_NEAR(normal, 0.9719, 1e-3);
  EXPECT_LE(normal, 1.0 + 1e-3);
  for (double thetaI : {0.3, 0.8, 1.2}) EXPECT_LE(albedo(white, thetaI, 0), 1.0 + 1e-3) << thetaI;

  const AnalyticBrdf plastic = AnalyticBrdf::preset("red-plastic");
  for (double thetaI : {0.0, 0.8}) {
    const double red = albedo(plastic, thetaI, 0), green = albedo(plastic, thetaI, 1);
    EXPECT_LT(red, 1.0) << thetaI;
    EXPECT_GT(red, 0.35) << thetaI;    // mostly the 0.5 base through the coat
    EXPECT_GT(green, 0.04) << thetaI;  // the white coat's reflection + the dark base
    EXPECT_LT(green, red) << thetaI;
  }
}

TEST(AnalyticBrdf, MerlTable) {
  const AnalyticBrdf brdf = AnalyticBrdf::preset("red-plastic");
  const std::vector<double> table = brdf.merlTable();
  ASSERT_EQ(table.size(), 3 * kN);
  for (int i = 0; i < 90; ++i)
    for (int j = 0; j < 90; ++j)
      for (int k = 0; k < 180; ++k) {
        const std::size_t index = MerlBrdf::flatIndex(i, j, k);
        if (merlCellBelowHorizon(i, j, k)) {
          for (int c = 0; c < 3; ++c) ASSERT_EQ(table[c * kN + index], -1.0);
          continue;
        }
        if (index % 1009 != 0) continue;
        const auto f = brdf.closedForm((i / 90.0) * (i / 90.0) * (kPi / 2), j / 90.0 * (kPi / 2), k / 180.0 * kPi);
        for (int c = 0; c < 3; ++c) {
          ASSERT_GE(table[c * kN + index], 0.0);
          ASSERT_NEAR(table[c * kN + index], f[c] / MerlBrdf::kChannelScale[c], 1e-12 * table[c * kN + index]);
        }
      }
}

TEST(AnalyticBrdf, ParametersAreValidated) {
  EXPECT_THROW(AnalyticBrdf::conductor(0.0, {1, 1, 1}), std::invalid_argument);
  EXPECT_THROW(AnalyticBrdf::conductor(std::nan(""), {1, 1, 1}), std::invalid_argument);
  EXPECT_THROW(AnalyticBrdf::conductor(0.1, {1, 1.01, 1}), std::invalid_argument);
  EXPECT_THROW(AnalyticBrdf::coatedDiffuse(0.1, {0.5, -0.1, 0.5}, 1.5), std::invalid_argument);
  EXPECT_THROW(AnalyticBrdf::coatedDiffuse(0.1, {0.5, 0.5, 0.5}, 0.9), std::invalid_argument);
  EXPECT_NO_THROW(AnalyticBrdf::coatedDiffuse(0.1, {0.5, 0.5, 0.5}, 1.0));
}

TEST(AnalyticBrdf, Presets) {
  const std::vector<std::string> names = AnalyticBrdf::presetNames();
  ASSERT_GE(names.size(), 3u);
  for (const std::string& name : names) {
    EXPECT_FALSE(AnalyticBrdf::presetDescription(name).empty());
    EXPECT_GT(AnalyticBrdf::preset(name).alpha(), 0.0);
  }
  EXPECT_EQ(AnalyticBrdf::preset("red-plastic").kind(), AnalyticBrdf::Kind::CoatedDiffuse);
  EXPECT_EQ(AnalyticBrdf::preset("gold").kind(), AnalyticBrdf::Kind::Conductor);
  try {
    AnalyticBrdf::preset("mithril");
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("gold"), std::string::npos) << e.what();
  }
}

}  // namespace
