#pragma once
// Analytic isotropic BRDFs with named presets, tabulated in the MERL layout by `acdf merl-gen
// --preset NAME` as test materials with a known closed form.
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

#include <array>
#include <string>
#include <vector>

namespace acdf {

struct AnalyticBrdf {
  enum class Kind { Conductor, CoatedDiffuse };

  Kind kind = Kind::Conductor;
  double alpha = 0.1;                           // GGX roughness, > 0
  std::array<double, 3> f0{1.0, 1.0, 1.0};      // Conductor: normal-incidence reflectance
  std::array<double, 3> albedo{0.5, 0.5, 0.5};  // CoatedDiffuse: the base's albedo
  double ior = 1.5;                             // CoatedDiffuse: the coat's refractive index

  // The BRDF at Rusinkiewicz angles (φh irrelevant). 0 when either direction is at or below
  // the horizon.
  std::array<double, 3> evalHalfDiff(double thetaHalf, double thetaDiff, double phiDiff) const;

  // The MERL table as NeuralBrdf::merlTable() builds it: cell corner coordinates, divided by
  // the channel scales, −1 in the cells NeuralBrdf::merlCellBelowHorizon marks. Parallel.
  std::vector<double> merlTable() const;

  // The named presets, and one line describing each ("name: model, parameters").
  static std::vector<std::string> presetNames();
  static std::string presetDescription(const std::string& name);
  // Throws std::invalid_argument naming the known presets for an unknown name.
  static AnalyticBrdf preset(const std::string& name);
};

}  // namespace acdf
