#pragma once
// Direct environment light at a shading point by resampled importance sampling of the product
// f·L·cos (Talbot, Cline & Egbert 2005): the light's table ignores f, the BSDF's sampler ignores L,
// and a lobe reflecting a small bright part of the map needs both.
//
// Candidates. X_1 … X_M are each drawn from the mixture
//   q(ω) = (1 − b) · p_light(ω) + b · p_bsdf(ω),      b = bsdfFraction,
// from a 2D point (u0, u1): the material's sampler at (u0 / b, u1) if u0 < b, else the light's
// table (the local one: the context carries the shading normal) at ((u0 − b) / (1 − b), u1).
// The points may be stratified (CandidateValues, sampler.h): only each one's law matters below.
// Each candidate is weighted by
//   w_i = p̂(X_i) / q(X_i),      p̂(ω) = lum(f(ωo, ω) ⊙ L(ω) · max(0, cosθ)),
// the luminance of the unoccluded integrand as the estimator computes it (float RGB, its Rec. 709
// weights summed in double, so p̂ > 0 exactly where that RGB is not black).
//
// Estimator. Y = X_j is chosen with probability w_j / Σ w (weighted reservoir sampling with one
// uniform value, exact up to its 53 bits); one shadow ray gives V(Y), and
//   F = f(Y) ⊙ L(Y) · cosθ_Y · V(Y) / p̂(Y) · (1/M) Σ_i w_i      (F = 0 when Σ w = 0).
//
// Unbiased. Write g = f ⊙ L · cos · V (RGB). Conditioning on the candidates (independent or not),
//   E[F | X] = Σ_j (w_j / Σ w) · g(X_j) / p̂(X_j) · (1/M) Σ w = (1/M) Σ_j w_j g(X_j) / p̂(X_j),
// and w_j / p̂(X_j) = 1 / q(X_j) where p̂(X_j) > 0 (the term is 0 elsewhere), so, each X_j having
// the law q,
//   E[F] = (1/M) Σ_j E[g(X_j) 1{p̂ > 0} / q(X_j)] = ∫_{q > 0, p̂ > 0} g dω,
// which is ∫ g dω exactly when p̂ > 0 and q > 0 wherever g ≠ 0:
//   - p̂: f, L ≥ 0 channel by channel and the luminance weights are positive, so p̂(ω) > 0 wherever
//     f ⊙ L · cos ≠ 0, in particular wherever g ≠ 0 (p̂ leaves out V, which only costs variance);
//   - q: for 0 < b < 1 one of the two densities suffices. Every BrdfSampler's pdf is positive
//     wherever f · cos > 0, so the light's table may be incomplete (the compensated one: pdf 0
//     where the map is dimmer than its mean); the context then allows it. b = 1 is BSDF sampling
//     alone (the light is only evaluated); b = 0 is light sampling alone, which needs a complete
//     table (p_light > 0 wherever L · cos > 0): the context must not allow an incomplete pdf.
// With M = 1 the estimator is g(X_1) / q(X_1): plain mixture sampling.
//
// The path's continuation. F estimates all the environment light reaching the point, so a
// BSDF-sampled continuation that escapes to the environment adds nothing (as under light-only
// MIS); it carries only indirect light. Camera rays that escape still see the map.
//
// Cost per candidate: one direction, f once, and both densities (the other strategy's pdf; the
// light's radiance from its table's pixel for a BSDF candidate); below the horizon, the direction
// alone. What the material's sampler finds from ωo alone (BrdfVertex: a table's slice) is found
// once per shading point, shared by the candidates and, when the caller passes its vertex, the
// path's continuation. Non-finite values never reach F: a candidate whose weight is not finite
// and positive counts as weight 0.

#include <cstdint>
#include <optional>

#include "acdf/brdf/brdf_sampler.h"
#include "acdf/envmap/environment_light.h"
#include "acdf/integrator/sampler.h"
#include "acdf/sampling/frame.h"
#include "acdf/sampling/rgb.h"

namespace acdf {

struct ProductSamplingOptions {
  // M, >= 1. More candidates lower the variance per sample less than they cost (and spend the
  // sample points' stratification): 2 had the best equal-time error on the scenes measured
  // (docs/performance.md, "Cheaper candidates").
  uint32_t candidates = 2;
  double bsdfFraction = 0.5;  // b, the mixture's weight of BSDF sampling, in [0, 1]
};

// Throws OptionError ("candidates", "bsdf_fraction").
void validate(const ProductSamplingOptions& options);

// The direction chosen and the estimate along it, before its shadow ray.
struct ProductLightSample {
  Vec3d direction;    // world frame, unit length
  Rgb estimate;       // f ⊙ L · cosθ / p̂ · (1/M) Σ w: F for V = 1, finite
  double mixturePdf;  // q at the direction, > 0
};

// One shading point: the light, the material, ωo and its frame. Cheap to make (no tables).
class ProductDirectLight {
 public:
  // `context` must carry the normal of `frame` (local tables; EnvironmentLight::atNormal also finds
  // its cell once for all the candidates) and allow an incomplete pdf only if
  // options.bsdfFraction > 0 (above). `wo` is in the local frame.
  ProductDirectLight(const EnvironmentLight& light, const LightSampleContext& context, const BrdfSampler& material,
                     const Frame& frame, const Vec3d& wo, const ProductSamplingOptions& options);
  // The same with the material at ωo already found.
  ProductDirectLight(const EnvironmentLight& light, const LightSampleContext& context, const BrdfVertex& material,
                     const Frame& frame, const ProductSamplingOptions& options);

  // Draws the M candidates, a point of `values` each, and chooses one with its resampling value;
  // none when every weight is 0.
  std::optional<ProductLightSample> sample(CandidateValues& values) const;
  // q at the world direction w (unit length).
  double mixturePdf(const Vec3d& w) const;

 private:
  struct Candidate {
    Vec3d direction;    // world
    Rgb integrand;      // f ⊙ L · max(0, cosθ)
    double target = 0;  // p̂
    double weight = 0;  // p̂ / q, or 0
    double mixturePdf = 0;
  };
  Candidate candidate(const std::array<float, 2>& u) const;
  // A candidate at `direction`, wi in the local frame and above the horizon.
  Candidate weighed(const Vec3d& direction, const Vec3d& wi, const Rgb& radiance, double lightPdf,
                    double bsdfPdf) const;

  const EnvironmentLight& light_;
  LightSampleContext context_;
  BrdfVertex material_;
  Frame frame_;
  ProductSamplingOptions options_;
};

}  // namespace acdf
