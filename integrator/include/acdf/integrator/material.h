#pragma once
// Surface materials, in the local shading frame (frame.h: z = the normal). Each one evaluates
// its BRDF and samples an incident direction with a density per steradian that pdf() reproduces,
// so the integrator can weigh BSDF sampling against light sampling (MIS).
//
//   DiffuseMaterial      f = ρ/π, cosine-weighted sampling (weight = ρ exactly);
//   MeasuredMaterial     a MERL table with any BrdfSampler (cosine, uniform or adaptive table);
//   GgxConductorMaterial acdf::AnalyticBrdf's GGX conductor evaluated in closed form, half
//                        vectors sampled ∝ D(ωh) cosθh: a measured material's analytic reference.

#include <memory>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/brdf_sampler.h"
#include "acdf/brdf/merl.h"
#include "acdf/integrator/color.h"
#include "acdf/sampling/sphere.h"

namespace acdf {

struct MaterialSample {
  Vec3d wi;        // local, unit
  Color weight;    // f(ωi, ωo) · max(cosθi, 0) / pdf
  double pdf = 0;  // per steradian; 0: no sample (the path ends)
};

class Material {
 public:
  virtual ~Material() = default;
  // f(ωi, ωo) in 1/sr; 0 unless both directions are above the surface.
  virtual Color eval(const Vec3d& wo, const Vec3d& wi) const = 0;
  virtual MaterialSample sample(const Vec3d& wo, float u0, float u1) const = 0;
  virtual double pdf(const Vec3d& wo, const Vec3d& wi) const = 0;
};

class DiffuseMaterial final : public Material {
 public:
  explicit DiffuseMaterial(const Color& albedo) : albedo_(albedo) {}
  Color eval(const Vec3d& wo, const Vec3d& wi) const override;
  MaterialSample sample(const Vec3d& wo, float u0, float u1) const override;
  double pdf(const Vec3d& wo, const Vec3d& wi) const override;

 private:
  Color albedo_;
};

class MeasuredMaterial final : public Material {
 public:
  // The sampler must sample `brdf` (it holds a reference to it; both are kept alive here).
  MeasuredMaterial(std::shared_ptr<const MerlBrdf> brdf, std::shared_ptr<const BrdfSampler> sampler);
  Color eval(const Vec3d& wo, const Vec3d& wi) const override;
  MaterialSample sample(const Vec3d& wo, float u0, float u1) const override;
  double pdf(const Vec3d& wo, const Vec3d& wi) const override;
  const BrdfSampler& sampler() const { return *sampler_; }

 private:
  std::shared_ptr<const MerlBrdf> brdf_;
  std::shared_ptr<const BrdfSampler> sampler_;
};

class GgxConductorMaterial final : public Material {
 public:
  // brdf.kind must be Conductor (throws std::invalid_argument otherwise).
  explicit GgxConductorMaterial(const AnalyticBrdf& brdf);
  Color eval(const Vec3d& wo, const Vec3d& wi) const override;
  MaterialSample sample(const Vec3d& wo, float u0, float u1) const override;
  double pdf(const Vec3d& wo, const Vec3d& wi) const override;

 private:
  // D(ωh) cosθh, the density of the sampled half vector per steradian.
  double halfVectorPdf(const Vec3d& wh) const;

  AnalyticBrdf brdf_;
};

}  // namespace acdf
