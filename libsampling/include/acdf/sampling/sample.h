#pragma once
// Result types shared by the distributions. Coordinates and densities are float, as a renderer
// consumes them; tables are built with double sums and stored as float (see each class).

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

namespace acdf {

// The largest float strictly below 1: the biggest value a [0,1) sample generator may return.
inline constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

// Most dimensions any grid distribution supports (conditioning plus sampled).
inline constexpr std::size_t kMaxDims = 8;

struct Sample1D {
  float x = 0;    // strictly inside the domain
  float pdf = 0;  // density w.r.t. length on the domain, finite and > 0
};

struct SampleND {
  std::array<float, kMaxDims> x{};  // the first `dims` entries are the sampled coordinates
  float pdf = 0;                    // density w.r.t. the product (Lebesgue) measure
  uint8_t dims = 0;

  // The sampled coordinates, ready for pdf() or invert().
  std::span<const float> point() const { return {x.data(), dims}; }
};

// Clamps a density into the positive finite float range. Products of per-dimension densities
// can underflow (1e-30 * 1e-30) or overflow in float; a returned sample must never report 0.
inline float clampDensity(double density) {
  if (!(density > 0.0)) return 0.0f;  // only unreachable points have density 0
  constexpr double kMin = std::numeric_limits<float>::denorm_min();
  constexpr double kMax = std::numeric_limits<float>::max();
  return static_cast<float>(std::clamp(density, kMin, kMax));
}

// Clamps a caller's uniform variate into [0, kOneMinusEpsilon]; NaN maps to 0.
inline float clampUnit(float u) {
  if (!(u >= 0.0f)) return 0.0f;
  return std::min(u, kOneMinusEpsilon);
}

// One variate choosing between two techniques and then reused by the chosen one: the first when
// u < share, with u / share, else the second with (u − share) / (1 − share); below 1 after
// rounding to float, so stratified variates stay stratified within each technique.
inline float rescaledVariate(double u, double share) {
  const double v = u < share ? u / share : (u - share) / (1.0 - share);
  return static_cast<float>(std::min(v, double{kOneMinusEpsilon}));
}

}  // namespace acdf
