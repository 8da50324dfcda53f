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

}  // namespace acdf
