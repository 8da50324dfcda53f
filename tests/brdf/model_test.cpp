// The BrdfModel interface (brdf_model.h) over its implementations — the MERL table with each
// interpolation, the analytic GGX models, Lambertian: f(ωo, ωi) is 0 below the horizon, its
// luminance is the Rec. 709 weighting of eval(), an isotropic model is unchanged when both
// directions turn about the normal, evalHalfDiff() is eval() at the angles' directions (MERL's
// and the analytic overrides, and the default through fromHalfDiff), and MERL models of one table
// share its values.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/coordinates.h"
#include "acdf/brdf/lambertian.h"
#include "acdf/brdf/merl.h"
#include "acdf/sampling/rng.h"

namespace {

using namespace acdf;
constexpr double kPi = std::numbers::pi;
using Interp = MerlBrdf::Interpolation;

// The red plastic preset in the MERL layout: a table smooth enough for trilinear lookups to
// follow it, with a diffuse part (no zero cells above the horizon).
const MerlBrdf& plasticTable() {
  static const MerlBrdf table = [] {
    const std::vector<double> raw = AnalyticBrdf::preset("red-plastic").merlTable();
    const std::span<const double> all(raw);
    const std::size_t n = MerlBrdf::kCells;
    return MerlBrdf(all.subspan(0, n), all.subspan(n, n), all.subspan(2 * n, n));
  }();
  return table;
}

struct NamedModel {
  std::string name;
  std::shared_ptr<const BrdfModel> model;
};

std::vector<NamedModel> models() {
  return {
      {"merl-nearest", std::make_shared<const MerlBrdf>(plasticTable())},
      {"merl-trilinear", std::make_shared<const MerlBrdf>(plasticTable().withInterpolation(Interp::Trilinear))},
      {"gold", std::make_shared<const AnalyticBrdf>(AnalyticBrdf::preset("gold"))},
      {"red-plastic", std::make_shared<const AnalyticBrdf>(AnalyticBrdf::preset("red-plastic"))},
      {"lambertian", std::make_shared<const LambertianBrdf>(Rgb{0.8f, 0.5f, 0.2f})},
  };
}

Vec3d upper(Pcg32& rng) { return sampleCosineHemisphere(rng.nextFloat(), rng.nextFloat()); }

Vec3d turnedAboutZ(const Vec3d& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}

// |a − b| within `relative` of the larger channel, per channel.
bool near(const Rgb& a, const Rgb& b, double relative) {
  const double scale = std::max({a.maxComponent(), b.maxComponent(), 1e-30f});
  return std::fabs(a.r - b.r) <= relative * scale && std::fabs(a.g - b.g) <= relative * scale &&
         std::fabs(a.b - b.b) <= relative * scale;
}

TEST(BrdfModel, LuminanceIsTheRec709WeightingOfEval) {
  Pcg32 rng(1);
  for (const NamedModel& m : models()) {
    int positive = 0;
    for (int n = 0; n < 2000; ++n) {
      const Vec3d wo = upper(rng), wi = upper(rng);
      const Rgb f = m.model->eval(wo, wi);
      positive += f.maxComponent() > 0.0f;
      ASSERT_EQ(m.model->luminance(wo, wi), f.luminance()) << m.name;
      ASSERT_NEAR(m.model->luminance(wo, wi), 0.2126 * f.r + 0.7152 * f.g + 0.0722 * f.b, 1e-6 * f.maxComponent());
    }
    EXPECT_GT(positive, 1900) << m.name;
  }
}

TEST(BrdfModel, ZeroAtAndBelowTheHorizon) {
  Pcg32 rng(2);
  for (const NamedModel& m : models()) {
    for (int n = 0; n < 200; ++n) {
      const Vec3d up = upper(rng), down = -upper(rng);
      const double phi = 2 * kPi * rng.nextDouble();
      const Vec3d grazing{std::cos(phi), std::sin(phi), 0.0};
      for (const auto& [wo, wi] : {std::pair{up, down}, {down, up}, {down, down}, {up, grazing}, {grazing, up}}) {
        ASSERT_EQ(m.model->eval(wo, wi), Rgb{}) << m.name;
        ASSERT_EQ(m.model->luminance(wo, wi), 0.0f) << m.name;
      }
    }
  }
}

// The property the tabulation relies on when isotropic() is true (one lattice for every φo).
TEST(BrdfModel, IsotropicModelsDoNotChangeWhenBothDirectionsTurn) {
  Pcg32 rng(3);
  for (const NamedModel& m : models()) {
    ASSERT_TRUE(m.model->isotropic()) << m.name;
    int differ = 0;
    const int pairs = 5000;
    for (int n = 0; n < pairs; ++n) {
      const Vec3d wo = upper(rng), wi = upper(rng);
      const double angle = 2 * kPi * rng.nextDouble();
      const Rgb f = m.model->eval(wo, wi), turned = m.model->eval(turnedAboutZ(wo, angle), turnedAboutZ(wi, angle));
      if (m.name == "merl-nearest") {
        differ += !(f == turned);  // a turn may round the angles across a cell boundary
      } else {
        ASSERT_TRUE(near(f, turned, 1e-5)) << m.name << " " << n;
      }
    }
    EXPECT_LE(differ, pairs / 1000) << m.name;
  }
}

// Where the angles give two directions above the horizon, evalHalfDiff() is eval() at them: the
// overrides (MERL's direct lookup, the analytic closed form) and the default through
// fromHalfDiff agree. Angles at MERL's cell centres, so a nearest lookup cannot round into the
// neighbouring cell.
TEST(BrdfModel, EvalHalfDiffIsEvalAtTheAnglesDirections) {
  Pcg32 rng(4);
  for (const NamedModel& m : models()) {
    int checked = 0;
    for (int n = 0; n < 20000; ++n) {
      const double thetaHalf = MerlBrdf::thetaHalfCentre(static_cast<int>(rng.nextDouble() * 90));
      const double thetaDiff = MerlBrdf::thetaDiffCentre(static_cast<int>(rng.nextDouble() * 90));
      const double phiDiff = MerlBrdf::phiDiffCentre(static_cast<int>(rng.nextDouble() * 180));
      const double phiHalf = (2 * rng.nextDouble() - 1) * kPi;
      const DirectionPair p = fromHalfDiff({thetaHalf, phiHalf, thetaDiff, phiDiff});
      if (!(p.wo.z > 1e-3 && p.wi.z > 1e-3)) continue;
      ++checked;
      const Rgb direct = m.model->evalHalfDiff(thetaHalf, thetaDiff, phiDiff);
      ASSERT_TRUE(near(direct, m.model->eval(p.wo, p.wi), 1e-5)) << m.name << " " << n;
      ASSERT_TRUE(near(direct, m.model->BrdfModel::evalHalfDiff(thetaHalf, thetaDiff, phiDiff), 1e-5))
          << m.name << " " << n;
    }
    EXPECT_GT(checked, 5000) << m.name;
  }
}

TEST(BrdfModel, MerlModelsOfOneTableShareItsValues) {
  const MerlBrdf& nearest = plasticTable();
  EXPECT_EQ(nearest.interpolation(), Interp::Nearest);
  const MerlBrdf trilinear = nearest.withInterpolation(Interp::Trilinear);
  EXPECT_EQ(trilinear.interpolation(), Interp::Trilinear);
  EXPECT_EQ(trilinear.negativeEntries(), nearest.negativeEntries());
  EXPECT_EQ(trilinear.interleavedValues().data(), nearest.interleavedValues().data());
  // And they evaluate differently between cell centres.
  const Vec3d wo = sphericalDirection(0.7, 0.1), wi = sphericalDirection(0.4, 2.9);
  EXPECT_NE(nearest.eval(wo, wi), trilinear.eval(wo, wi));
}

TEST(BrdfModel, LambertianIsAlbedoOverPiAndValidatesIt) {
  const LambertianBrdf m(Rgb{0.8f, 0.5f, 0.2f});
  const Rgb f = m.eval({0, 0, 1}, sphericalDirection(1.2, 0.4));
  EXPECT_FLOAT_EQ(f.r, 0.8f / kPi);
  EXPECT_FLOAT_EQ(f.g, 0.5f / kPi);
  EXPECT_FLOAT_EQ(f.b, 0.2f / kPi);
  EXPECT_THROW(LambertianBrdf(Rgb{1.5f, 0.5f, 0.5f}), std::invalid_argument);
  EXPECT_THROW(LambertianBrdf(Rgb{0.5f, -0.1f, 0.5f}), std::invalid_argument);
  EXPECT_THROW(LambertianBrdf(Rgb{0.5f, 0.5f, std::nanf("")}), std::invalid_argument);
}

}  // namespace
