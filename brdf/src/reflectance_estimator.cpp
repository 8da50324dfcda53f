#include "acdf/brdf/reflectance_estimator.h"

#include <algorithm>
#include <chrono>
#include <numbers>
#include <stdexcept>

#include "acdf/sampling/rng.h"

namespace acdf {

ReflectanceEstimate estimateReflectance(const BrdfSampler& sampler, const ReflectanceEstimatorOptions& o) {
  if (o.thetaCount == 0 || o.phiCount == 0 || o.samplesPerDirection == 0)
    throw std::invalid_argument("reflectance estimator: direction and sample counts must be > 0");
  if (!(o.maxThetaOut > 0.0 && o.maxThetaOut < 0.5 * std::numbers::pi))
    throw std::invalid_argument("reflectance estimator: maxThetaOut must be in (0, pi/2)");

  ReflectanceEstimate result;
  double meanSum = 0.0, varianceSum = 0.0;
  const auto start = std::chrono::steady_clock::now();
  for (uint32_t t = 0; t < o.thetaCount; ++t)
    for (uint32_t p = 0; p < o.phiCount; ++p) {
      const double thetaOut = (t + 0.5) / o.thetaCount * o.maxThetaOut;
      const double phiOut = (p + 0.5) / o.phiCount * 2.0 * std::numbers::pi;
      const Vec3d wo = sphericalDirection(thetaOut, phiOut);
      Pcg32 rng(o.seed, uint64_t{t} * o.phiCount + p);
      double sum = 0.0, sumSquares = 0.0, largest = 0.0;
      for (uint32_t k = 0; k < o.samplesPerDirection; ++k) {
        const float u0 = rng.nextFloat(), u1 = rng.nextFloat();
        const BrdfSample s = sampler.sample(wo, u0, u1);
        double y = s.weight.luminance();
        if (o.incident && y != 0.0) y *= o.incident(s.wi);
        sum += y;
        sumSquares += y * y;
        largest = std::max(largest, y);
      }
      const double n = o.samplesPerDirection;
      const double mean = sum / n;
      meanSum += mean;
      varianceSum += std::max(0.0, sumSquares / n - mean * mean);
      if (mean > 0.0) result.maxRelativeWeight = std::max(result.maxRelativeWeight, largest / mean);
    }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double directions = static_cast<double>(o.thetaCount) * o.phiCount;
  result.mean = meanSum / directions;
  result.variance = varianceSum / directions;
  result.samples = uint64_t{o.thetaCount} * o.phiCount * o.samplesPerDirection;
  return result;
}

}  // namespace acdf
