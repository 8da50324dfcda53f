#include "acdf/brdf/rgl_sampler.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "acdf/brdf/half_vector.h"

namespace acdf {

RglBrdfSampler::RglBrdfSampler(std::shared_ptr<const RglBrdf> model) : BrdfSampler(model), rgl_(*model) {}

Vec3d RglBrdfSampler::sampleDirection(const Vec3d& wo, float u0, float u1) const {
  if (!(wo.z > 0.0)) return sampleCosineHemisphere(u0, u1);
  const std::array<float, 2> params = RglBrdf::parameters(wo);
  const float u[2] = {u0, u1};
  const SampleND s = rgl_.luminanceWarp().sample(params, u);
  const SampleND um = rgl_.vndfWarp().sample(params, std::span<const float>(s.x.data(), 2));
  const Vec3d wm = RglBrdf::halfVector(std::span<const float>(um.x.data(), 2), params[0]);
  return normalize(reflect(wo, wm));
}

double RglBrdfSampler::halfVectorPdf(const Vec3d& wo, const Vec3d& wm) const {
  if (!(wm.z > 0.0)) return 0.0;
  const std::array<float, 2> params = RglBrdf::parameters(wo);
  const double thetaM = RglBrdf::elevation(wm);
  const std::array<float, 2> um = RglBrdf::unitCoordinates(thetaM, std::atan2(wm.y, wm.x) - params[0]);
  const std::array<float, 2> s = rgl_.vndfWarp().invert(params, um);
  const double density = static_cast<double>(rgl_.luminanceWarp().pdf(params, s)) * rgl_.vndfWarp().pdf(params, um);
  // dωm / (du dv); at the normal itself (a set of measure zero) the smallest positive value keeps
  // the density finite.
  const double jacobian = 2.0 * std::numbers::pi * std::numbers::pi * um[1] * std::sin(thetaM);
  return density / std::max(jacobian, std::numeric_limits<double>::min());
}

double RglBrdfSampler::pdf(const Vec3d& wo, const Vec3d& wi) const {
  if (!(wo.z > 0.0)) return cosineHemispherePdf(wi.z);
  const std::optional<HalfVector> h = halfVectorOf(wo, wi);
  return h ? h->incidentPdf(halfVectorPdf(wo, h->direction)) : 0.0;
}

}  // namespace acdf
