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
//
// Guiding (guiding_field.h, renderer.h). Two fields learned from earlier passes may join in:
//   - the light field: what of the environment each place sees. Light samples then come from
//       p_light'(ω) = b · p_field(ω) + (1 − b) · p_light(ω),      b = kLightFieldShare,
//     u0 choosing the technique, and p_light' replaces p_light in both MIS weights (the light's
//     radiance is the map's either way). With the light alone (light-only MIS) p_light is complete,
//     so p_light' is; under MIS the BSDF covers what neither density reaches, as before.
//   - the path field: the radiance paths carried. A vertex whose material is guided
//     (guidedMaterial) continues from
//       q(ω) = a · p_bsdf(ω) + (1 − a) · p_field(ω),      a = kGuidedBsdfShare,
//     the BSDF sample's first value choosing the technique; the weight is f · cosθ / q, and q
//     replaces p_bsdf in both MIS weights. Unbiased because p_bsdf > 0 wherever f · cos > 0.
// What a path records for them, where the render asks (PathGuiding): for the light field, each
// light sample's map radiance where unblocked (0 where blocked or below the surface) over its
// density, and each escaped continuation's radiance over its density; for the path field, each
// vertex's continuation and the radiance that arrived along it, as the image counts it (what the
// path added after the vertex, rescaled to it, escapes with their MIS weight): a field that learned
// the light its own light samples already find would spend the continuations on it again.

#include <cstdint>
#include <vector>

#include "acdf/integrator/guiding_field.h"
#include "acdf/integrator/sampler.h"
#include "acdf/integrator/scene.h"
#include "acdf/sampling/frame.h"

namespace acdf {

// What guiding gives one path: the field to sample from (none: the BSDF alone) and where to record
// what its vertices learn (none: nothing is recorded).
struct PathGuiding {
  const GuidingField* field = nullptr;
  std::vector<GuidingRecord>* records = nullptr;
  // The environment light as each place sees it, and where its records go.
  const GuidingField* lightField = nullptr;
  std::vector<GuidingRecord>* lightRecords = nullptr;
};

class PathIntegrator {
 public:
  explicit PathIntegrator(const Scene& scene);

  // Radiance arriving along the camera ray, with the sampler started on its pixel sample and its
  // pixel dimensions taken; `rays` counts the rays cast (intersect + shadow).
  Rgb radiance(const Ray& cameraRay, Sampler& sampler, uint64_t& rays, const PathGuiding& guiding = {}) const;

  // The BSDF's share of the guided mixture.
  static constexpr double kGuidedBsdfShare = 0.5;
  // The learned field's share of light sampling.
  static constexpr double kLightFieldShare = 0.5;
  // A material is guided when its density towards the mirror direction at normal incidence is at
  // most this (a Lambertian surface's is 1/π, GGX α = 0.2's about 2, α = 0.05's about 32): guiding
  // learns radiance, not its product with the BSDF, and a narrow lobe's own sampler beats it.
  static constexpr double kGuidedPeakDensity = 1.0;
  static bool guidedMaterial(const BrdfSampler& sampler);

 private:
  // The direction a vertex continues along, in the world frame, with f · cosθ / density and the
  // density; density 0 when the path ends there.
  struct Continuation {
    Vec3d direction;
    Rgb weight;
    double pdf = 0;
  };
  Continuation continuation(const BrdfVertex& material, const Frame& frame, const DirectionalDistribution* guide,
                            float u0, float u1) const;
  // The density of continuing along world direction w (local wi) at the vertex.
  double continuationPdf(const BrdfVertex& material, const DirectionalDistribution* guide, const Vec3d& wi,
                         const Vec3d& w) const;
  // A light sample at a vertex: from the light's own sampler, or with a field, from the mixture
  //   p(ω) = b · p_field(ω) + (1 − b) · p_light(ω),      b = kLightFieldShare,
  // u0 choosing the technique.
  LightSample lightSample(const LightSampleContext& context, const DirectionalDistribution* field, float u0,
                          float u1) const;
  // That mixture's radiance and density along w.
  RadianceAndPdf lightAlong(const LightSampleContext& context, const DirectionalDistribution* field,
                            const Vec3d& w) const;
  // The MIS weight of a strategy with density `chosen` against one with density `other`.
  double misWeight(double chosen, double other) const;

  const Scene& scene_;
  std::vector<bool> guided_;  // per material
};

}  // namespace acdf
