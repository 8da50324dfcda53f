#include "acdf/brdf/reflectance_estimator.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "acdf/sampling/rng.h"

namespace acdf {

namespace {

void validateDirections(const ReflectanceEstimatorOptions& o) {
  if (o.thetaCount == 0 || o.phiCount == 0)
    throw std::invalid_argument("reflectance estimator: direction counts must be > 0");
  if (!(o.maxThetaOut > 0.0 && o.maxThetaOut < 0.5 * std::numbers::pi))
    throw std::invalid_argument("reflectance estimator: maxThetaOut must be in (0, pi/2)");
}

double outgoingTheta(const ReflectanceEstimatorOptions& o, uint32_t t) {
  return (t + 0.5) / o.thetaCount * o.maxThetaOut;
}
double outgoingPhi(const ReflectanceEstimatorOptions& o, uint32_t p) {
  return (p + 0.5) / o.phiCount * 2.0 * std::numbers::pi;
}

}  // namespace

ReflectanceEstimate estimateReflectance(const BrdfSampler& sampler, const ReflectanceEstimatorOptions& o) {
  validateDirections(o);
  if (o.samplesPerDirection == 0) throw std::invalid_argument("reflectance estimator: sample count must be > 0");

  ReflectanceEstimate result;
  double meanSum = 0.0, varianceSum = 0.0;
  const auto start = std::chrono::steady_clock::now();
  for (uint32_t t = 0; t < o.thetaCount; ++t)
    for (uint32_t p = 0; p < o.phiCount; ++p) {
      const Vec3d wo = sphericalDirection(outgoingTheta(o, t), outgoingPhi(o, p));
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

ReflectanceQuadrature integrateReflectance(const BrdfSampler& sampler, const ReflectanceEstimatorOptions& o,
                                           const ReflectanceQuadratureOptions& grid) {
  validateDirections(o);
  if (grid.thetaHalfPoints == 0 || grid.phiHalfPoints == 0)
    throw std::invalid_argument("reflectance quadrature: point counts must be > 0");
  constexpr double kPi = std::numbers::pi;
  const uint32_t ns = grid.thetaHalfPoints, nphi = grid.phiHalfPoints;

  // Per s point: sinθh, cosθh and the weight dωh / (ds dφ) = sinθh · dθh/ds, times the cell.
  std::vector<double> sinHalf(ns), cosHalf(ns), halfWeight(ns);
  const double cellArea = (1.0 / ns) * (2.0 * kPi / nphi);
  for (uint32_t i = 0; i < ns; ++i) {
    const double s = (i + 0.5) / ns;
    const double thetaHalf = s * s * 0.5 * kPi;
    sinHalf[i] = std::sin(thetaHalf);
    cosHalf[i] = std::cos(thetaHalf);
    halfWeight[i] = sinHalf[i] * kPi * s * cellArea;
  }

  struct Sums {
    double mean = 0, secondMoment = 0, unsampled = 0;
  };
  const uint32_t directions = o.thetaCount * o.phiCount;
  std::vector<Sums> perDirection(directions);
  tbb::parallel_for(uint32_t{0}, directions, [&](uint32_t d) {
    const double phiOut = outgoingPhi(o, d % o.phiCount);
    const Vec3d wo = sphericalDirection(outgoingTheta(o, d / o.phiCount), phiOut);
    std::vector<double> cosPhi(nphi), sinPhi(nphi);
    for (uint32_t k = 0; k < nphi; ++k) {
      const double phiHalf = phiOut + (k + 0.5) / nphi * 2.0 * kPi;
      cosPhi[k] = std::cos(phiHalf);
      sinPhi[k] = std::sin(phiHalf);
    }
    Sums sums;
    for (uint32_t i = 0; i < ns; ++i)
      for (uint32_t k = 0; k < nphi; ++k) {
        const Vec3d wh{sinHalf[i] * cosPhi[k], sinHalf[i] * sinPhi[k], cosHalf[i]};
        const double cosOutHalf = dot(wo, wh);
        const Vec3d wi = reflect(wo, wh);
        if (!(cosOutHalf > 0.0) || !(wi.z > 0.0)) continue;
        double g = sampler.eval(wo, wi).luminance() * wi.z;
        if (o.incident && g != 0.0) g *= o.incident(wi);
        if (g == 0.0) continue;
        const double dwi = 4.0 * cosOutHalf * halfWeight[i];
        sums.mean += g * dwi;
        const double pdf = sampler.pdf(wo, wi);
        if (pdf > 0.0)
          sums.secondMoment += g * g / pdf * dwi;
        else
          sums.unsampled += g * dwi;
      }
    perDirection[d] = sums;
  });

  ReflectanceQuadrature result;
  for (const Sums& s : perDirection) {
    result.mean += s.mean;
    const double sampledMean = s.mean - s.unsampled;  // what the estimator converges to
    result.variance += std::max(0.0, s.secondMoment - sampledMean * sampledMean);
    result.unsampled += s.unsampled;
  }
  result.mean /= directions;
  result.variance /= directions;
  result.unsampled /= directions;
  return result;
}

}  // namespace acdf
