#include "acdf/brdf/rgl_sampler.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "acdf/brdf/half_vector.h"

namespace acdf {

RglBrdfSampler::RglBrdfSampler(std::shared_ptr<const RglBrdf> model) : BrdfSampler(model), rgl_(*model) {}

namespace {

// p(ωm) per steradian from the density of um = (v, u) on the unit square, at θm = u²·π/2:
// dωm / (du dv) = 2π² u sinθm. At the normal itself (a set of measure zero) the smallest positive
// Jacobian keeps the density finite.
double perSteradian(double unitDensity, float u, double thetaM) {
  const double jacobian = 2.0 * std::numbers::pi * std::numbers::pi * u * std::sin(thetaM);
  return unitDensity / std::max(jacobian, std::numeric_limits<double>::min());
}

}  // namespace

// The density at the sampled s and um themselves (pbrt-v4's MeasuredBxDF::Sample_f): inverting
// um back to s in float can land one ulp into a neighbouring cell of zero luminance density.
SampledDirection RglBrdfSampler::sampleDirection(const Vec3d& wo, float u0, float u1) const {
  if (!(wo.z > 0.0)) return sampleCosineDirection(u0, u1);
  const std::array<float, 2> params = RglBrdf::parameters(wo);
  const float u[2] = {u0, u1};
  const SampleND s = rgl_.luminanceWarp().sample(params, u);
  const SampleND um = rgl_.vndfWarp().sample(params, s.point());
  const Vec3d wm = RglBrdf::halfVector(um.point(), params[0]);
  const double thetaM = static_cast<double>(um.x[1]) * um.x[1] * (0.5 * std::numbers::pi);
  const double density = perSteradian(static_cast<double>(s.pdf) * um.pdf, um.x[1], thetaM);
  return {normalize(reflect(wo, wm)), sampledHalfVector(wo, wm).incidentPdf(density)};
}

double RglBrdfSampler::halfVectorPdf(const Vec3d& wo, const Vec3d& wm) const {
  if (!(wm.z > 0.0)) return 0.0;
  const std::array<float, 2> params = RglBrdf::parameters(wo);
  const double thetaM = RglBrdf::elevation(wm);
  const std::array<float, 2> um = RglBrdf::unitCoordinates(thetaM, std::atan2(wm.y, wm.x) - params[0]);
  const std::array<float, 2> s = rgl_.vndfWarp().invert(params, um);
  const double density = static_cast<double>(rgl_.luminanceWarp().pdf(params, s)) * rgl_.vndfWarp().pdf(params, um);
  return perSteradian(density, um[1], thetaM);
}

double RglBrdfSampler::pdf(const Vec3d& wo, const Vec3d& wi) const {
  if (!(wo.z > 0.0)) return cosineHemispherePdf(wi.z);
  const std::optional<HalfVector> h = halfVectorOf(wo, wi);
  return h ? h->incidentPdf(halfVectorPdf(wo, h->direction)) : 0.0;
}

HalfVectorDensity RglBrdfSampler::halfVectorDensity(const Vec3d& wo) const {
  return {.cosineShare = 0,
          .sCells = 64,
          .phiCells = 32,
          .phiOrigin = azimuth(wo) - std::numbers::pi,  // the warps' v = 0 is φm = φo − π
          .density = [this, wo](const Vec3d& wm) { return halfVectorPdf(wo, wm); },
          .uniformInS = true};
}

}  // namespace acdf
