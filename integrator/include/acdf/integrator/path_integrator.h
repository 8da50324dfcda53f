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
// Branched at the first vertex into K paths (after its light sample), each branch continues with
// its own BSDF sample and a 1/K share: the mean of K unbiased estimates of the light after vertex
// 0, so unbiased for any K; the MIS weights are per sample, as without branches.
// Connected to light paths (light_paths.h), each vertex x within the maximum depth also connects to
// one vertex y of its sample's pool (picked by its light sample's second value): a third technique
// for the paths x → y → ω whose last bounce the sun lights through a portal. Those paths' three
// weights are the MIS heuristic over a · p_light,y(ω), a · p_bsdf,y(ω) and p_C(y, ω), with
// a = p_bsdf,x(x → y) cosθ_y / |x − y|² the density per unit area of x's BSDF sample reaching y:
// the light sample and the escape at y use them in place of the two-way weights wherever the
// vertex before y connected (y not the camera's first vertex).
// Russian roulette from RenderSettings::rouletteDepth on: survive with probability
// min(0.95, max throughput channel), dividing the throughput by it. Light sampling may use an
// incomplete pdf (a compensated table) exactly when BSDF samples see the light too
// (allowsIncompleteLightPdf); its samples and the MIS weights of escaped BSDF samples then use the
// same one. The random values come from a Sampler, in the order sampler.h lists.
//
// The BSDF and the light are techniques (direction_techniques.h): each draws a direction and answers
// its density for any direction, which is all the MIS weights need. Guiding (guiding_field.h,
// renderer.h) mixes a field learned in earlier passes into a technique (GuidedMixture):
//   - the light field: what of the environment each place sees, into light sampling with the
//     light's tables' share kGuidedLightShare. The mixture's density replaces p_light in both MIS
//     weights (the light's radiance is the map's either way). With the light alone (light-only MIS)
//     p_light is complete, so the mixture is; under MIS the BSDF covers what neither density
//     reaches, as before.
//   - the path field: the radiance paths carried, into the continuations of guided materials
//     (guidedMaterial) with the BSDF's share kGuidedBsdfShare; the weight is f · cosθ / q and q
//     replaces p_bsdf in both MIS weights. Unbiased because p_bsdf > 0 wherever f · cos > 0.
// What a path records for them, where the render asks (PathGuiding): for the light field, each
// light sample's map radiance where unblocked (0 where blocked or below the surface) over its
// density, and each escaped continuation's radiance over its density; for the path field, each
// vertex's continuation and the radiance that arrived along it, as the image counts it (what the
// path added after the vertex, rescaled to it, escapes with their MIS weight): a field that learned
// the light its own light samples already find would spend the continuations on it again.

#include <cstdint>
#include <vector>

#include "acdf/integrator/camera.h"
#include "acdf/integrator/direction_techniques.h"
#include "acdf/integrator/geometry.h"
#include "acdf/integrator/guiding_field.h"
#include "acdf/integrator/light_paths.h"
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

// Rays a path cast (closest hit and shadow), and how many of them after its first vertex's light
// sample: what a branch costs (RenderSettings::branches). And of the continuations (the rays after
// a BSDF sample) how many escaped: where most do, the map's pixel along the next one is loaded while
// it is traced (EnvironmentLight::prefetch); where most hit, that would be wasted work.
struct RayCounts {
  uint64_t total = 0, afterFirstVertex = 0;
  uint64_t continuations = 0, escapes = 0;
  void add(uint32_t depth) {
    ++total;
    afterFirstVertex += depth > 0;
  }
  bool escapesLikely() const { return 2 * escapes > continuations; }
};

class PathIntegrator {
 public:
  explicit PathIntegrator(const Scene& scene);

  // Radiance arriving along the camera ray, with the sampler started on its pixel sample and its
  // pixel dimensions taken; it adds the rays it casts to `rays`. The path branches
  // `branches` ways at its first vertex (RenderSettings::branches).
  // `lightPaths`, if given (the pool of the sample's index), is what each vertex connects to
  // (light_paths.h); only under balance or power MIS with light samples, unguided.
  Rgb radiance(const Ray& cameraRay, Sampler& sampler, RayCounts& rays, const PathGuiding& guiding = {},
               uint32_t branches = 1, const LightPathPool* lightPaths = nullptr) const;

  // The BSDF's share of guided continuations, and the light's tables' share of guided light samples.
  static constexpr double kGuidedBsdfShare = 0.5;
  static constexpr double kGuidedLightShare = 0.5;
  // A material is guided when its density towards the mirror direction at normal incidence is at
  // most this (a Lambertian surface's is 1/π, GGX α = 0.2's about 2, α = 0.05's about 32): guiding
  // learns radiance, not its product with the BSDF, and a narrow lobe's own sampler beats it.
  static constexpr double kGuidedPeakDensity = 1.0;
  static bool guidedMaterial(const BrdfSampler& sampler);

 private:
  class PathRecorder;
  // What a path carries from one vertex to the next.
  struct PathState {
    // Built member by member: a defaulted constructor zero-fills the whole context, portal views
    // and all (about 600 bytes), on every camera sample.
    PathState(const Ray& cameraRay, bool allowIncompleteLightPdf)
        : ray(cameraRay), lightContext{.allowIncompletePdf = allowIncompleteLightPdf} {}
    Ray ray;                     // the ray to the next vertex
    Rgb throughput{1, 1, 1};
    double bsdfPdf = 0;          // density of the sample that produced `ray`; 0 for the camera ray
    LightSampleContext lightContext;
    // The learned light at the vertex `ray` left, and that vertex.
    DirectionalDistribution lightField;
    Vec3d lastPosition, lastNormal;
    // Per unit area at that vertex, the density of its being reached from the vertex before it by
    // that vertex's BSDF sample, where a connection from there covers it too (else 0).
    double reachedDensity = 0;
  };
  // The path from `state` on, its first vertex at `firstDepth` (branching `branches` ways there if it
  // is vertex 0): the light it brings to the image.
  Rgb walk(PathState& state, uint32_t firstDepth, uint32_t branches, Sampler& sampler, RayCounts& rays,
           const PathGuiding& guiding, const LightPathPool* lightPaths, PathRecorder& recorder) const;
  // The light a connection from vertex `hit` (its material, frame and continuation `bsdf`) to the
  // light path vertex `light` brings, before the path's throughput (0 where blocked).
  Rgb connect(const SurfaceHit& hit, const BrdfVertex& material, const Frame& frame,
              const GuidedMixture<BsdfTechnique>& bsdf, const LightVertex& light, double successShare,
              RayCounts& rays, uint32_t depth) const;
  // Continues `state` from its vertex `hit` at `depth` along a BSDF sample, with `share` of its
  // weight, through Russian roulette: false where the path ends.
  bool extend(PathState& state, const SurfaceHit& hit, const GuidedMixture<BsdfTechnique>& bsdf, uint32_t depth,
              float share, Sampler& sampler, PathRecorder& recorder) const;
  // The light at a vertex seen from `context`, mixed with the light field there (none: the light alone).
  GuidedMixture<LightTechnique> guidedLight(const LightSampleContext& context, DirectionalDistribution field) const;
  // The MIS weight of a strategy with density `chosen` against others with densities `other` and
  // `third` (all in one measure).
  double misWeight(double chosen, double other, double third = 0) const;
  // The weight of a light or BSDF sample with density `chosen` (against `other`, the vertex's other
  // technique, per steradian) at a vertex reached with density `reached` per unit area, where a
  // connection from the vertex before has density `connection` (light_paths.h; 0: none).
  double misWeightBesideConnection(double chosen, double other, double reached, double connection) const;

  const Scene& scene_;
  std::vector<bool> guided_;  // per material
};

}  // namespace acdf
