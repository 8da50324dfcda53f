#include "acdf/envmap/irradiance_estimator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "acdf/sampling/frame.h"
#include "acdf/sampling/rng.h"

namespace acdf {

namespace {

std::vector<Vec3d> fibonacciNormals(uint32_t count) {
  std::vector<Vec3d> normals;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (uint32_t k = 0; k < count; ++k) {
    const double y = 1.0 - (2.0 * k + 1.0) / count;
    const double r = std::sqrt(1.0 - y * y);
    normals.push_back({r * std::cos(golden * k), y, r * std::sin(golden * k)});
  }
  return normals;
}

std::vector<double> exactIrradiance(const EnvironmentMap& map, const std::vector<Vec3d>& normals) {
  std::vector<double> irradiance(normals.size(), 0.0);
  for (uint32_t r = 0; r < map.height(); ++r) {
    const double solidAngle = map.mapping().pixelSolidAngle(r);
    for (uint32_t c = 0; c < map.width(); ++c) {
      const double L = map.radiance(PixelIndex{r, c}).luminance();
      if (L == 0) continue;
      const Vec3d w = map.mapping().directionInPixel({r, c}, 0.5, 0.5);
      for (std::size_t k = 0; k < normals.size(); ++k)
        irradiance[k] += L * solidAngle * std::max(0.0, dot(normals[k], w));
    }
  }
  return irradiance;
}

}  // namespace

IrradianceEstimator::IrradianceEstimator(const EnvironmentMap& map, IrradianceEstimatorOptions options)
    : options_(options) {
  if (options_.normals == 0 || options_.samplesPerNormal == 0 || options_.strata == 0)
    throw std::invalid_argument("irradiance estimator: counts must be >= 1");
  if (options_.samplesPerNormal % (options_.strata * options_.strata) != 0)
    throw std::invalid_argument("irradiance estimator: samples per normal must be a multiple of strata^2");
  normals_ = fibonacciNormals(options_.normals);
  exact_ = exactIrradiance(map, normals_);
}

IrradianceCost IrradianceEstimator::measure(const IrradianceSampler& sampler, bool stratified) const {
  const uint32_t samples = options_.samplesPerNormal, strata = options_.strata;
  IrradianceCost cost;
  Pcg32 rng(options_.seed);
  double relativeVariance = 0;
  uint32_t lit = 0;
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < normals_.size(); ++k) {
    double squaredError = 0;
    for (uint32_t i = 0; i < samples; ++i) {
      const double x = sampler(normals_[k], rng.nextFloat(), rng.nextFloat());
      squaredError += (x - exact_[k]) * (x - exact_[k]);
    }
    if (exact_[k] > 0) {
      relativeVariance += squaredError / samples / (exact_[k] * exact_[k]);
      ++lit;
    }
  }
  cost.nsPerSample = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count() /
                     (static_cast<double>(normals_.size()) * samples);
  cost.variance = lit > 0 ? relativeVariance / lit : 0.0;
  cost.efficiency = cost.variance > 0 ? 1.0 / (cost.variance * cost.nsPerSample * 1e-9) : 0.0;
  if (!stratified) return cost;

  const double perTrial = static_cast<double>(strata) * strata;
  const uint32_t trials = options_.stratifiedTrials();
  relativeVariance = 0;
  for (std::size_t k = 0; k < normals_.size(); ++k) {
    if (!(exact_[k] > 0)) continue;
    double squaredError = 0;
    for (uint32_t t = 0; t < trials; ++t) {
      double sum = 0;
      for (uint32_t i = 0; i < strata; ++i)
        for (uint32_t j = 0; j < strata; ++j) {
          const float u0 = (static_cast<float>(i) + rng.nextFloat()) / static_cast<float>(strata);
          const float u1 = (static_cast<float>(j) + rng.nextFloat()) / static_cast<float>(strata);
          sum += sampler(normals_[k], u0, u1);
        }
      squaredError += (sum / perTrial - exact_[k]) * (sum / perTrial - exact_[k]);
    }
    relativeVariance += perTrial * squaredError / trials / (exact_[k] * exact_[k]);
  }
  cost.stratifiedVariance = lit > 0 ? relativeVariance / lit : 0.0;
  return cost;
}

IrradianceSampler lightSamplingEstimator(const EnvironmentLight& light) {
  return [&light](const Vec3d& n, float u0, float u1) {
    const LightSample s = light.sample({.normal = n}, u0, u1);
    return s.radiance.luminance() * std::max(0.0, dot(n, s.direction)) / s.pdf;
  };
}

IrradianceSampler uniformSphereEstimator(const EnvironmentLight& light) {
  return [&light](const Vec3d& n, float u0, float u1) {
    const Vec3d w = sampleUniformSphere(u0, u1);
    return light.eval(w).luminance() * std::max(0.0, dot(n, w)) / kUniformSpherePdf;
  };
}

IrradianceSampler cosineEstimator(const EnvironmentLight& light) {
  return [&light](const Vec3d& n, float u0, float u1) {
    const Vec3d w = Frame(n).toWorld(sampleCosineHemisphere(u0, u1));
    return light.eval(w).luminance() * std::numbers::pi;  // Y(L) cos θ / (cos θ / π)
  };
}

}  // namespace acdf
