#include "acdf/brdf/brdf_sampler.h"

#include <stdexcept>

#include "acdf/sampling/sample.h"

namespace acdf {

BrdfSampler::BrdfSampler(std::shared_ptr<const BrdfModel> model) : model_(std::move(model)) {
  if (!model_) throw std::invalid_argument("BRDF sampler: no BRDF model");
}

BrdfSample BrdfVertex::sample(float u0, float u1) const {
  const SampledDirection d = sampleDirection(u0, u1);
  BrdfSample s;
  s.wi = d.wi;
  s.pdf = d.pdf;
  if (s.wi.z > 0.0 && wo_.z > 0.0) s.weight = eval(s.wi) * static_cast<float>(s.wi.z / s.pdf);
  return s;
}

SampledDirection BrdfVertex::sampleDirection(float u0, float u1) const {
  return sampler_->sampleDirectionAt(*this, clampUnit(u0), clampUnit(u1));
}

double BrdfVertex::pdf(const Vec3d& wi) const { return sampler_->pdfAt(*this, wi); }

Rgb BrdfVertex::eval(const Vec3d& wi) const { return sampler_->eval(wo_, wi); }

SampledDirection BrdfSampler::reflected(const BrdfVertex& v, const Vec3d& wi, const HalfVector& h,
                                        double density) const {
  if (!h.roundTripExact())
    if (const double p = v.pdf(wi); p > 0.0) return {wi, p};
  return {wi, density};
}

double CosineBrdfSampler::pdf(const Vec3d&, const Vec3d& wi) const { return cosineHemispherePdf(wi.z); }

SampledDirection CosineBrdfSampler::sampleDirection(const Vec3d&, float u0, float u1) const {
  return sampleCosineDirection(u0, u1);
}

HalfVectorDensity BrdfSampler::halfVectorDensity(const Vec3d&) const { return {}; }

}  // namespace acdf
