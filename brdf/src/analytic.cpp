#include "acdf/brdf/analytic.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "acdf/brdf/coordinates.h"
#include "acdf/brdf/ggx_sampler.h"
#include "acdf/brdf/merl.h"
#include "acdf/brdf/merl_tabulation.h"

namespace acdf {

namespace {

constexpr double kPi = std::numbers::pi;

struct Preset {
  const char* name;
  const char* description;
  AnalyticBrdf (*make)();
};

// F0 of gold and aluminium: linear RGB values from Real-Time Rendering (4th ed.), table 9.2.
const Preset kPresets[] = {
    {"gold", "GGX conductor, alpha 0.15, Schlick F0 (1.000, 0.766, 0.336)",
     [] {
       return AnalyticBrdf::conductor(0.15, {1.000, 0.766, 0.336});
     }},
    {"rough-aluminium", "GGX conductor, alpha 0.4, Schlick F0 (0.913, 0.922, 0.924)",
     [] {
       return AnalyticBrdf::conductor(0.4, {0.913, 0.922, 0.924});
     }},
    {"red-plastic", "diffuse albedo (0.5, 0.05, 0.05) under a GGX coat, alpha 0.08, ior 1.5",
     [] {
       return AnalyticBrdf::coatedDiffuse(0.08, {0.5, 0.05, 0.05}, 1.5);
     }},
};

void checkUnitChannels(const std::array<double, 3>& rgb, const char* what) {
  for (double v : rgb)
    if (!(v >= 0.0 && v <= 1.0)) throw std::invalid_argument(std::string("analytic BRDF: ") + what + " outside [0, 1]");
}

double schlick(double f0, double cosine) {
  const double m = 1.0 - std::clamp(cosine, 0.0, 1.0);
  return f0 + (1.0 - f0) * (m * m) * (m * m) * m;
}

Rgb toRgb(const std::array<double, 3>& f) {
  return {static_cast<float>(f[0]), static_cast<float>(f[1]), static_cast<float>(f[2])};
}

}  // namespace

AnalyticBrdf::AnalyticBrdf(Kind kind, double alpha, const std::array<double, 3>& f0,
                           const std::array<double, 3>& albedo, double ior)
    : kind_(kind), alpha_(alpha), f0_(f0), albedo_(albedo), ior_(ior) {
  if (!(std::isfinite(alpha) && alpha > 0.0))
    throw std::invalid_argument("analytic BRDF: alpha must be finite and > 0");
  checkUnitChannels(f0, "F0");
  checkUnitChannels(albedo, "albedo");
  if (!(std::isfinite(ior) && ior >= 1.0))
    throw std::invalid_argument("analytic BRDF: the index of refraction must be finite and >= 1");
}

AnalyticBrdf AnalyticBrdf::conductor(double alpha, const std::array<double, 3>& f0) {
  return AnalyticBrdf(Kind::Conductor, alpha, f0, {0.0, 0.0, 0.0}, 1.0);
}

AnalyticBrdf AnalyticBrdf::coatedDiffuse(double alpha, const std::array<double, 3>& albedo, double ior) {
  return AnalyticBrdf(Kind::CoatedDiffuse, alpha, {0.0, 0.0, 0.0}, albedo, ior);
}

std::array<double, 3> AnalyticBrdf::closedForm(double thetaHalf, double thetaDiff, double phiDiff) const {
  const DirectionPair p = fromHalfDiff({thetaHalf, 0.0, thetaDiff, phiDiff});
  return fromCosines(p.wi.z, p.wo.z, std::cos(thetaHalf), std::cos(thetaDiff));
}

std::array<double, 3> AnalyticBrdf::fromCosines(double cosI, double cosO, double cosHalf, double cosDiff) const {
  if (!(cosI > 0 && cosO > 0)) return {0.0, 0.0, 0.0};
  const double specular =
      ggxDistribution(alpha_, cosHalf) * ggxMasking(alpha_, cosI) * ggxMasking(alpha_, cosO) / (4.0 * cosI * cosO);
  std::array<double, 3> f{};
  if (kind_ == Kind::Conductor) {
    for (int c = 0; c < 3; ++c) f[c] = schlick(f0_[c], cosDiff) * specular;
  } else {
    const double r = (ior_ - 1.0) / (ior_ + 1.0), coatF0 = r * r;
    const double coat = schlick(coatF0, cosDiff) * specular;
    const double transmitted = (1.0 - schlick(coatF0, cosI)) * (1.0 - schlick(coatF0, cosO));
    for (int c = 0; c < 3; ++c) f[c] = coat + transmitted * albedo_[c] / kPi;
  }
  return f;
}

Rgb AnalyticBrdf::evalHalfDiff(double thetaHalf, double thetaDiff, double phiDiff) const {
  return toRgb(closedForm(thetaHalf, thetaDiff, phiDiff));
}

Rgb AnalyticBrdf::eval(const Vec3d& wo, const Vec3d& wi) const {
  if (!(wo.z > 0 && wi.z > 0)) return {};
  // cos θh and cos θd straight from the half vector: the angles themselves (two atan2 there, and
  // sines and cosines back here) are not needed.
  const Vec3d h = normalize(wo + wi);
  return toRgb(fromCosines(wi.z, wo.z, h.z, dot(wi, h)));
}

std::string AnalyticBrdf::addToKey(ContentHash&) const {
  if (kind_ == Kind::Conductor)
    return fmt::format("analytic-ggx conductor alpha={:a} f0={:a},{:a},{:a}", alpha_, f0_[0], f0_[1], f0_[2]);
  return fmt::format("analytic-ggx coated-diffuse alpha={:a} albedo={:a},{:a},{:a} ior={:a}", alpha_, albedo_[0],
                     albedo_[1], albedo_[2], ior_);
}

std::vector<double> AnalyticBrdf::merlTable() const {
  return tabulateMerl(
      [this](const MerlCellCoordinates& cell) { return closedForm(cell.thetaHalf, cell.thetaDiff, cell.phiDiff); });
}

std::vector<std::string> AnalyticBrdf::presetNames() {
  std::vector<std::string> names;
  for (const Preset& p : kPresets) names.emplace_back(p.name);
  return names;
}

std::string AnalyticBrdf::presetDescription(const std::string& name) {
  for (const Preset& p : kPresets)
    if (name == p.name) return p.description;
  throw std::invalid_argument("no preset named '" + name + "'");
}

AnalyticBrdf AnalyticBrdf::preset(const std::string& name) {
  for (const Preset& p : kPresets)
    if (name == p.name) return p.make();
  std::string known;
  for (const Preset& p : kPresets) known += (known.empty() ? "" : ", ") + std::string(p.name);
  throw std::invalid_argument("no preset named '" + name + "' (presets: " + known + ")");
}

std::shared_ptr<const BrdfSampler> AnalyticBrdf::nativeSampler(const std::shared_ptr<const BrdfModel>& self) const {
  checkIsSelf(*this, self);
  return std::make_shared<const GgxBrdfSampler>(std::static_pointer_cast<const AnalyticBrdf>(self));
}

}  // namespace acdf
