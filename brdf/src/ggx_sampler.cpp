#include "acdf/brdf/ggx_sampler.h"

#include <cmath>

#include "acdf/brdf/half_vector.h"

namespace acdf {

// BrdfSampler's constructor has refused a null model before alpha_ is read.
GgxBrdfSampler::GgxBrdfSampler(std::shared_ptr<const AnalyticBrdf> model)
    : BrdfSampler(model), alpha_(model->alpha()) {}

double GgxBrdfSampler::visibleNormalPdf(const Vec3d& wo, const Vec3d& wh) const {
  const double cosOut = dot(wo, wh);
  if (!(wh.z > 0.0) || !(cosOut > 0.0) || !(wo.z > 0.0)) return 0.0;
  return ggxMasking(alpha_, wo.z) * cosOut * ggxDistribution(alpha_, wh.z) / wo.z;
}

SampledDirection GgxBrdfSampler::sampleDirection(const Vec3d& wo, float u0, float u1) const {
  if (!(wo.z > 0.0)) return sampleCosineDirection(u0, u1);
  // ωo where the microsurface is the unit hemisphere; the visible normals there are uniform on the
  // cap of directions whose z is above −ωo's, and each one plus ωo points along a visible normal.
  const Vec3d view = normalize(Vec3d{alpha_ * wo.x, alpha_ * wo.y, wo.z});
  const double z = (1.0 - static_cast<double>(u0)) * (1.0 + view.z) - view.z;  // in (−view.z, 1]
  const Vec3d normal = directionAtTurns(z, std::sqrt(std::fmax(0.0, 1.0 - z * z)), u1) + view;
  const Vec3d wh = normalize(Vec3d{alpha_ * normal.x, alpha_ * normal.y, normal.z});
  const HalfVector h = sampledHalfVector(wo, wh);
  return reflected(vertex(wo), normalize(reflect(wo, wh)), h, h.incidentPdf(visibleNormalPdf(wo, wh)));
}

double GgxBrdfSampler::pdf(const Vec3d& wo, const Vec3d& wi) const {
  if (!(wo.z > 0.0)) return cosineHemispherePdf(wi.z);
  const std::optional<HalfVector> h = halfVectorOf(wo, wi);
  return h ? h->incidentPdf(visibleNormalPdf(wo, h->direction)) : 0.0;
}

HalfVectorDensity GgxBrdfSampler::halfVectorDensity(const Vec3d& wo) const {
  return {.cosineShare = 0,
          .sCells = 256,
          .phiCells = 32,
          .density = [this, wo](const Vec3d& wh) { return visibleNormalPdf(wo, wh); }};
}

}  // namespace acdf
