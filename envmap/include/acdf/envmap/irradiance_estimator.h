#pragma once
// The fixed Monte Carlo estimator the environment-light samplers are compared by (`acdf
// envmap-stats`), beside brdf/'s reflectance estimator: the irradiance
// E(n) = ∫ Y(L(ω)) max(0, n·ω) dω of a map at `normals` normals spread evenly over the sphere (a
// Fibonacci lattice), `samplesPerNormal` one-sample estimates X each, variates from Pcg32(seed).
// The exact E(n) is the pixel-centre sum over the map as it is sampled (radiance constant per
// pixel). Reported variance: the mean over the normals with E > 0 of E[(X − E)²] / E².
//
// Stratified variant: the same samples per normal spent on samplesPerNormal / strata² estimates,
// each the mean over a jittered strata × strata set of variates; n × E[(mean − E)²] / E² with
// n = strata², which equals the variance when stratification gains nothing and is lower by the
// factor it gains.

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/environment_map.h"
#include "acdf/sampling/sphere.h"

namespace acdf {

struct IrradianceEstimatorOptions {
  uint32_t normals = 64;
  uint32_t samplesPerNormal = 4096;  // a multiple of strata²
  uint64_t seed = 1;
  uint32_t strata = 16;

  uint32_t stratifiedTrials() const { return samplesPerNormal / (strata * strata); }
};

// One estimate X of E(normal) from the variates (u0, u1): a direction, its pdf, weighted.
using IrradianceSampler = std::function<double(const Vec3d& normal, float u0, float u1)>;

struct IrradianceCost {
  double variance = 0;
  std::optional<double> stratifiedVariance;  // when measured
  double nsPerSample = 0;                    // wall-clock, one thread, plain estimates only
  double efficiency = 0;                     // 1 / (variance × seconds per sample)
};

class IrradianceEstimator {
 public:
  // The normals and their exact irradiance under `map`. Throws std::invalid_argument for zero
  // counts or a samplesPerNormal that is not a multiple of strata².
  explicit IrradianceEstimator(const EnvironmentMap& map, IrradianceEstimatorOptions options = {});

  // Stratified estimates only when `stratified`: uniform-sphere and cosine weights are
  // heavy-tailed (a sun hit is rare and huge), which few trials per normal cannot average.
  IrradianceCost measure(const IrradianceSampler& sampler, bool stratified) const;

  const std::vector<Vec3d>& normals() const { return normals_; }
  const std::vector<double>& exact() const { return exact_; }
  const IrradianceEstimatorOptions& options() const { return options_; }

 private:
  IrradianceEstimatorOptions options_;
  std::vector<Vec3d> normals_;
  std::vector<double> exact_;
};

// The estimators compared: the light's own samples (for the normal: a local light samples its
// slice), and two that ignore the map (`light` only evaluates it): uniform directions over the
// sphere and cosine-weighted ones about the normal.
IrradianceSampler lightSamplingEstimator(const EnvironmentLight& light);
IrradianceSampler uniformSphereEstimator(const EnvironmentLight& light);
IrradianceSampler cosineEstimator(const EnvironmentLight& light);

}  // namespace acdf
