#pragma once
// The fixed Monte Carlo estimator the BRDF samplers are compared by (the paper's Table 1): the
// radiance reflected towards ωo, L(ωo) = ∫ f(ωi, ωo) cosθi L_in(ωi) dωi, estimated with one
// sample Y = luminance(weight) · L_in(ωi) per draw, for a fixed stratified set of ωo.
//
// ωo: thetaCount × phiCount directions, θo at the centres of thetaCount equal strata of
// [0, maxThetaOut], φo likewise over [0, 2π). Each direction draws `samplesPerDirection` samples
// from its own Pcg32 stream of `seed`, so the figures are deterministic and thread-count free.
// Reported variance: the per-sample variance Var[Y | ωo], averaged over the directions (what a
// renderer's noise at a fixed sample count is proportional to).

#include <cstdint>
#include <functional>

#include "acdf/brdf/brdf_sampler.h"

namespace acdf {

struct ReflectanceEstimatorOptions {
  uint32_t thetaCount = 16, phiCount = 4;
  double maxThetaOut = 85.0 * 3.14159265358979323846 / 180.0;  // radians
  uint32_t samplesPerDirection = 4096;
  uint64_t seed = 0x9E3779B97F4A7C15ULL;
  // Incident radiance (luminance) from ωi in the local frame; empty = 1 everywhere (a uniform
  // white environment, so L(ωo) is the BRDF's directional albedo).
  std::function<double(const Vec3d& wi)> incident;
};

struct ReflectanceEstimate {
  double mean = 0;      // L(ωo) averaged over the directions
  double variance = 0;  // Var[Y | ωo] averaged over the directions
  // The largest single Y over all directions, relative to that direction's mean: how far above
  // the estimate one sample can land (a firefly); 1 for a zero-variance sampler.
  double maxRelativeWeight = 0;
  uint64_t samples = 0;
  double seconds = 0;  // wall-clock time drawing and weighting the samples (single thread)

  double nsPerSample() const { return samples ? seconds * 1e9 / samples : 0.0; }
  // 1 / (variance × seconds per sample): inverse of the time to reach unit variance.
  double efficiency() const { return variance > 0 && seconds > 0 ? samples / (variance * seconds) : 0.0; }
};

// Throws std::invalid_argument for zero counts or a maxThetaOut outside (0, π/2).
ReflectanceEstimate estimateReflectance(const BrdfSampler& sampler, const ReflectanceEstimatorOptions& options = {});

// The same figures without sampling noise, so tables a few percent apart can be ranked: for each
// ωo of the estimator's set,
//   E[Y | ωo] = ∫ g dωi,   Var[Y | ωo] = ∫ g² / pdf dωi − E[Y | ωo]²,   g = luminance(f)·cosθi·L_in,
// from the sampler's pdf() and the model's f, by the midpoint rule over the half vector ωh
// (dωi = 4(ωo·ωh) dωh): θh on the tables' square-root scale s = √(θh / (π/2)), so points crowd at
// the specular peak, and Δφ = φh − φo. At multiples of a table's s and φ cell counts every table
// cell holds the same number of points (the estimator's φo fall on cell boundaries), so a
// piecewise-constant pdf is integrated exactly and the error is the model's and the cosine's.
struct ReflectanceQuadratureOptions {
  // 4× the default tables' half-vector cells per axis: doubling both counts leaves an analytic
  // GGX lobe converged and moves the ratio of two tables' variances of a MERL material (nearest-
  // cell f, discontinuous) far less than the variances themselves (acdf brdf-stats --help
  // gives the figures).
  uint32_t thetaHalfPoints = 1024, phiHalfPoints = 128;
};

struct ReflectanceQuadrature {
  double mean = 0;      // E[Y | ωo] averaged over the directions
  double variance = 0;  // Var[Y | ωo] averaged over the directions
  // The part of `mean` where pdf = 0: what the sampler never draws, so its estimator's bias
  // (0 for a sampler that covers f·cosθi; `variance` leaves those points out).
  double unsampled = 0;
};

// Directions are integrated in parallel (options.incident is called concurrently); the result
// does not depend on the thread count. Throws std::invalid_argument as estimateReflectance does
// (samplesPerDirection and seed are unused), and for a zero point count.
ReflectanceQuadrature integrateReflectance(const BrdfSampler& sampler, const ReflectanceEstimatorOptions& options = {},
                                           const ReflectanceQuadratureOptions& grid = {});

}  // namespace acdf
