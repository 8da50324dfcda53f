#pragma once
// Analytic isotropic BRDFs with named presets: evaluated in closed form as BrdfModels (the
// renderer's ggx-conductor material) and tabulated in the MERL layout by `acdf merl-gen --preset
// NAME`, as test materials with a known closed form.
//
// Both models use the GGX (Trowbridge-Reitz) microfacet distribution with roughness α, Smith's
// separable shadowing G1(ω) = 2 / (1 + √(1 + α² tan²θ)), and Schlick's Fresnel
// F(cos) = F0 + (1 − F0)(1 − cos)⁵ evaluated at cos θd = ωi·h:
//
//   Conductor:      f = F(θd) D(θh) G1(ωi) G1(ωo) / (4 cos θi cos θo),   F0 = the metal's RGB
//   CoatedDiffuse:  f = the same specular lobe with F0 = ((n − 1)/(n + 1))² (dielectric coat)
//                     + (1 − F(θi)) (1 − F(θo)) · albedo / π              (diffuse base under it)
//
// with D(θh) = α² / (π cos⁴θh (α² + tan²θh)²). Both are reciprocal; values in 1/sr, linear RGB.
// GgxBrdfSampler (ggx_sampler.h) samples the half vectors ωo sees, from D and G1(ωo).

#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "acdf/brdf/brdf_model.h"

namespace acdf {

// The model's GGX terms, which its sampler and the RGL files synthesised from it use too: D at a
// half vector of cosine cosHalf, written α² / (π (cos²θh (α² − 1) + 1)²), and Smith's G1 of a
// direction of cosine cosTheta > 0.
inline double ggxDistribution(double alpha, double cosHalf) {
  const double a2 = alpha * alpha, denominator = cosHalf * cosHalf * (a2 - 1.0) + 1.0;
  return a2 / (std::numbers::pi * denominator * denominator);
}
inline double ggxMasking(double alpha, double cosTheta) {
  const double c2 = cosTheta * cosTheta;
  const double tan2 = (1.0 - c2) / c2;
  return 2.0 / (1.0 + std::sqrt(1.0 + alpha * alpha * tan2));
}

class AnalyticBrdf final : public BrdfModel {
 public:
  enum class Kind { Conductor, CoatedDiffuse };

  // Throw std::invalid_argument unless α is finite and > 0, every F0 or albedo channel in [0, 1]
  // and the index of refraction finite and >= 1.
  static AnalyticBrdf conductor(double alpha, const std::array<double, 3>& f0);
  static AnalyticBrdf coatedDiffuse(double alpha, const std::array<double, 3>& albedo, double ior);

  Kind kind() const { return kind_; }
  double alpha() const { return alpha_; }                          // GGX roughness
  const std::array<double, 3>& f0() const { return f0_; }          // Conductor: normal-incidence reflectance
  const std::array<double, 3>& albedo() const { return albedo_; }  // CoatedDiffuse: the base's albedo
  double ior() const { return ior_; }                              // CoatedDiffuse: the coat's refractive index

  // The closed form at Rusinkiewicz angles (φh irrelevant), in double. 0 when either direction
  // is at or below the horizon.
  std::array<double, 3> closedForm(double thetaHalf, double thetaDiff, double phiDiff) const;

  // closedForm() at the directions' angles, rounded to float (computed from the directions'
  // cosines, without the angles).
  Rgb eval(const Vec3d& wo, const Vec3d& wi) const override;
  Rgb evalHalfDiff(double thetaHalf, double thetaDiff, double phiDiff) const override;
  bool isotropic() const override { return true; }
  // No data; the kind and its parameters: "analytic-ggx conductor alpha=... f0=...".
  std::string addToKey(ContentHash& content) const override;
  // GGX sampling of its lobe (GgxBrdfSampler).
  std::shared_ptr<const BrdfSampler> nativeSampler(const std::shared_ptr<const BrdfModel>& self) const override;

  // The MERL table as NeuralBrdf::merlTable() builds it (tabulateMerl, merl_tabulation.h).
  std::vector<double> merlTable() const;

  // The named presets, and one line describing each ("name: model, parameters").
  static std::vector<std::string> presetNames();
  static std::string presetDescription(const std::string& name);
  // Throws std::invalid_argument naming the known presets for an unknown name.
  static AnalyticBrdf preset(const std::string& name);

 private:
  // The closed form given cos θi, cos θo (to the normal), cos θh and cos θd; 0 unless both
  // directions are above the horizon.
  std::array<double, 3> fromCosines(double cosI, double cosO, double cosHalf, double cosDiff) const;

  AnalyticBrdf(Kind kind, double alpha, const std::array<double, 3>& f0, const std::array<double, 3>& albedo,
               double ior);

  Kind kind_;
  double alpha_;
  std::array<double, 3> f0_, albedo_;
  double ior_;
};

}  // namespace acdf
