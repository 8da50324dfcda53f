#include "acdf/brdf/brdf_sampler.h"

#include "acdf/sampling/sample.h"

namespace acdf {

BrdfSample BrdfSampler::sample(const Vec3d& wo, float u0, float u1) const {
  BrdfSample s;
  s.wi = sampleDirection(wo, clampUnit(u0), clampUnit(u1));
  // The pdf of the final direction, not of the path that produced it: mixtures and half-vector
  // reflections reach ωi in more than one way, and pdf() sums them all.
  s.pdf = pdf(wo, s.wi);
  if (s.wi.z > 0.0 && wo.z > 0.0) {
    const Rgb f = brdf_.eval(s.wi, wo, interpolation_);
    const auto scale = static_cast<float>(s.wi.z / s.pdf);
    s.weight = {f.r * scale, f.g * scale, f.b * scale};
  }
  return s;
}

double CosineBrdfSampler::pdf(const Vec3d&, const Vec3d& wi) const { return cosineHemispherePdf(wi.z); }

Vec3d CosineBrdfSampler::sampleDirection(const Vec3d&, float u0, float u1) const {
  return sampleCosineHemisphere(u0, u1);
}

}  // namespace acdf
