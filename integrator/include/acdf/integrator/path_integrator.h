#pragma once
// Unidirectional path tracing with next-event estimation on the environment and BSDF sampling,
// combined by multiple importance sampling (Veach 1997, ch. 9). At each surface vertex:
//
//   light sample  ω_l ~ p_light:  f(ω_l) cosθ_l L(ω_l) / p_light · w_light(ω_l)   if unoccluded
//   BSDF sample   ω_b ~ p_bsdf:   continues the path; if it escapes, L(ω_b) · w_bsdf(ω_b)
//
// with w_light + w_bsdf = 1 for every direction both strategies can produce:
//   power    w_x = p_x² / (p_light² + p_bsdf²)     balance  w_x = p_x / (p_light + p_bsdf)
//   bsdf-only  w_bsdf = 1, no light samples        light-only  w_light = 1, escapes add nothing
// (both densities per steradian). Camera rays that escape see the environment directly.
// Under product direct lighting (RenderSettings::direct) the light sample and its MIS weights give
// way to one resampled estimate of all the direct light (product_direct_light.h, one shadow ray);
// BSDF samples then only continue the path, and escapes add nothing, as under light-only.
// Russian roulette from RenderSettings::rouletteDepth on: survive with probability
// min(0.95, max throughput channel), dividing the throughput by it. Light sampling may use an
// incomplete pdf (a compensated table) exactly when BSDF samples see the light too
// (allowsIncompleteLightPdf); its samples and the MIS weights of escaped BSDF samples then use the
// same one. The random values come from a Sampler, in the order sampler.h lists.

#include <cstdint>

#include "acdf/integrator/sampler.h"
#include "acdf/integrator/scene.h"

namespace acdf {

class PathIntegrator {
 public:
  explicit PathIntegrator(const Scene& scene) : scene_(scene) {}

  // Radiance arriving along the camera ray, with the sampler started on its pixel sample and its
  // pixel dimensions taken; `rays` counts the rays cast (intersect + shadow).
  Rgb radiance(const Ray& cameraRay, Sampler& sampler, uint64_t& rays) const;

 private:
  // The MIS weight of a strategy with density `chosen` against one with density `other`.
  double misWeight(double chosen, double other) const;

  const Scene& scene_;
};

}  // namespace acdf
