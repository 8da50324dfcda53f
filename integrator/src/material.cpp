#include "acdf/integrator/material.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "acdf/brdf/coordinates.h"

namespace acdf {

// ---- Diffuse -------------------------------------------------------------------------------

Color DiffuseMaterial::eval(const Vec3d& wo, const Vec3d& wi) const {
  if (wo.z <= 0 || wi.z <= 0) return {};
  return albedo_ * std::numbers::inv_pi;
}

MaterialSample DiffuseMaterial::sample(const Vec3d& wo, float u0, float u1) const {
  MaterialSample s;
  s.wi = sampleCosineHemisphere(u0, u1);
  s.pdf = cosineHemispherePdf(s.wi.z);
  // f cosθi / pdf = (ρ/π) cosθi / (cosθi/π) = ρ.
  s.weight = wo.z > 0 ? albedo_ : Color{};
  return s;
}

double DiffuseMaterial::pdf(const Vec3d&, const Vec3d& wi) const { return cosineHemispherePdf(wi.z); }

// ---- Measured ------------------------------------------------------------------------------

MeasuredMaterial::MeasuredMaterial(std::shared_ptr<const MerlBrdf> brdf, std::shared_ptr<const BrdfSampler> sampler)
    : brdf_(std::move(brdf)), sampler_(std::move(sampler)) {
  if (&sampler_->brdf() != brdf_.get())
    throw std::invalid_argument("MeasuredMaterial: the sampler samples another BRDF");
}

Color MeasuredMaterial::eval(const Vec3d& wo, const Vec3d& wi) const {
  return Color(brdf_->eval(wi, wo, sampler_->interpolation()));
}

MaterialSample MeasuredMaterial::sample(const Vec3d& wo, float u0, float u1) const {
  const BrdfSample s = sampler_->sample(wo, u0, u1);
  return {s.wi, Color(s.weight), s.pdf};
}

double MeasuredMaterial::pdf(const Vec3d& wo, const Vec3d& wi) const { return sampler_->pdf(wo, wi); }

// ---- GGX conductor -------------------------------------------------------------------------

GgxConductorMaterial::GgxConductorMaterial(const AnalyticBrdf& brdf) : brdf_(brdf) {
  if (brdf.kind != AnalyticBrdf::Kind::Conductor) throw std::invalid_argument("GgxConductorMaterial: not a conductor");
}

Color GgxConductorMaterial::eval(const Vec3d& wo, const Vec3d& wi) const {
  if (wo.z <= 0 || wi.z <= 0) return {};
  const HalfDiffAngles a = toHalfDiff(wi, wo);
  const auto f = brdf_.evalHalfDiff(a.thetaHalf, a.thetaDiff, a.phiDiff);
  return {f[0], f[1], f[2]};
}

// D(θh) = α² / (π cos⁴θh (α² + tan²θh)²); its projection D cosθh integrates to 1 over the
// hemisphere. Inverting its CDF: tan²θh = α² u / (1 − u).
double GgxConductorMaterial::halfVectorPdf(const Vec3d& wh) const {
  if (wh.z <= 0) return 0;
  const double cos2 = wh.z * wh.z, tan2 = (1.0 - cos2) / cos2, a2 = brdf_.alpha * brdf_.alpha;
  const double D = a2 / (std::numbers::pi * cos2 * cos2 * (a2 + tan2) * (a2 + tan2));
  return D * wh.z;
}

MaterialSample GgxConductorMaterial::sample(const Vec3d& wo, float u0, float u1) const {
  const double u = std::fmin(u0, 1.0 - 0x1p-40);  // u → 1 is the horizon, where D cosθh = 0
  const double tan2 = brdf_.alpha * brdf_.alpha * u / (1.0 - u);
  const double cosTheta = 1.0 / std::sqrt(1.0 + tan2);
  const Vec3d wh = sphericalDirection(std::acos(cosTheta), 2.0 * std::numbers::pi * u1);
  MaterialSample s;
  s.wi = normalize(reflect(wo, wh));
  s.pdf = pdf(wo, s.wi);
  if (s.pdf > 0) s.weight = eval(wo, s.wi) * (std::fmax(s.wi.z, 0.0) / s.pdf);
  return s;
}

// p(ωi) = p(ωh) / (4 |ωo·ωh|), ωh = normalize(ωi + ωo) (the Jacobian of the reflection).
double GgxConductorMaterial::pdf(const Vec3d& wo, const Vec3d& wi) const {
  const Vec3d sum = wi + wo;
  if (!(length(sum) > 0)) return 0;
  Vec3d wh = normalize(sum);
  if (wh.z < 0) wh = -wh;
  const double cosD = std::abs(dot(wo, wh));
  return cosD > 0 ? halfVectorPdf(wh) / (4.0 * cosD) : 0;
}

}  // namespace acdf
