#include "acdf/brdf/ggx_sampler.h"

#include <cmath>
#include <numbers>

#include "acdf/brdf/half_vector.h"

namespace acdf {

// BrdfSampler's constructor has refused a null model before alpha_ is read.
GgxBrdfSampler::GgxBrdfSampler(std::shared_ptr<const AnalyticBrdf> model)
    : BrdfSampler(model), alpha_(model->alpha()) {}

// D(θh) = α² / (π cos⁴θh (α² + tan²θh)²).
double GgxBrdfSampler::halfVectorPdf(const Vec3d& wh) const {
  if (wh.z <= 0) return 0;
  const double cos2 = wh.z * wh.z, tan2 = (1.0 - cos2) / cos2, a2 = alpha_ * alpha_;
  const double d = a2 / (std::numbers::pi * cos2 * cos2 * (a2 + tan2) * (a2 + tan2));
  return d * wh.z;
}

SampledDirection GgxBrdfSampler::sampleDirection(const Vec3d& wo, float u0, float u1) const {
  if (!(wo.z > 0.0)) return sampleCosineDirection(u0, u1);
  const double u = std::fmin(u0, 1.0 - 0x1p-40);  // u → 1 is the horizon, where D cosθh = 0
  const double tan2 = alpha_ * alpha_ * u / (1.0 - u);
  const double cosTheta = 1.0 / std::sqrt(1.0 + tan2);
  const Vec3d wh = directionAtTurns(cosTheta, std::sqrt(tan2) * cosTheta, u1);  // sinθ = tanθ·cosθ, without acos
  const HalfVector h = sampledHalfVector(wo, wh);
  return reflected(vertex(wo), normalize(reflect(wo, wh)), h, h.incidentPdf(halfVectorPdf(wh)));
}

double GgxBrdfSampler::pdf(const Vec3d& wo, const Vec3d& wi) const {
  if (!(wo.z > 0.0)) return cosineHemispherePdf(wi.z);
  const std::optional<HalfVector> h = halfVectorOf(wo, wi);
  return h ? h->incidentPdf(halfVectorPdf(h->direction)) : 0.0;
}

HalfVectorDensity GgxBrdfSampler::halfVectorDensity(const Vec3d&) const {
  return {.cosineShare = 0, .sCells = 256, .phiCells = 32, .density = [this](const Vec3d& wh) { return halfVectorPdf(wh); }};
}

}  // namespace acdf
