#pragma once
// A procedural sun-and-sky environment map, for demos and tests: a sky gradient, a glow around
// the sun, a uniform ground and a small, very bright sun disk. Not a physical sky model; what
// matters is the shape real maps share (a smooth sky and a tiny peak holding much of the power).
//
// In the map frame of lat_long.h (+Y up), for a direction ω with cos θ = ω.y and angle γ to the
// sun's centre:
//   sky    (ω.y > 0):  horizon + (zenith − horizon) · (ω.y)^gradient
//                      + glow · sunColor · exp(−γ / glowWidth)
//   ground (ω.y ≤ 0):  ground
//   sun    (γ ≤ sunRadius): sunIntensity · sunColor, replacing the sky
// Each pixel holds the sky (or ground) at its centre; pixels the sun disk may touch are
// supersampled (kSunSupersampling² points, uniform in solid angle), so a sun smaller than a pixel
// still covers the right fraction of it.
//
// Presets (sunSkyPreset()), azimuths as the map's φ (0: −Z, 90°: +X, 180°: +Z, 270°: −X):
//   noon       sun 60° high at azimuth 90°, radius 0.27°, 1e5 × the zenith; blue sky.
//   afternoon  sun 25° high at azimuth 200°, radius 0.27°, 5e4; paler sky, wider glow.
//   sunset     sun 2° high at azimuth 270°, radius 0.4°, 5e3, orange; orange horizon, dark zenith.
//   overcast   no sun; gray sky three times brighter at the zenith than at the horizon.

#include <cstdint>
#include <string>
#include <vector>

#include "acdf/envmap/image_file.h"
#include "acdf/sampling/rgb.h"

namespace acdf {

struct SunSkyParameters {
  double sunElevationDeg = 60;  // above the horizon, [−90, 90]
  double sunAzimuthDeg = 90;    // the map's φ (lat_long.h), degrees: 0 is −Z, 90 is +X
  double sunRadiusDeg = 0.27;   // angular radius, >= 0 (0: no sun)
  double sunIntensity = 1e5;    // sun radiance / sunColor, >= 0 (0: no sun)
  Rgb sunColor{1.0f, 0.95f, 0.88f};
  Rgb zenith{0.25f, 0.45f, 1.0f};
  Rgb horizon{0.8f, 0.85f, 1.0f};
  double gradient = 0.5;     // > 0; smaller: the zenith colour reaches lower
  double glow = 0.5;         // >= 0
  double glowWidthDeg = 10;  // > 0
  Rgb ground{0.12f, 0.1f, 0.08f};
};

inline constexpr uint32_t kSunSupersampling = 8;

// Throws std::invalid_argument for an unknown name (listing the known ones).
SunSkyParameters sunSkyPreset(const std::string& name);
std::vector<std::string> sunSkyPresetNames();

// A width × height RGB image (width, height >= 1). Throws std::invalid_argument for parameters
// outside the ranges above.
Image sunSkyImage(uint32_t width, uint32_t height, const SunSkyParameters& parameters);

}  // namespace acdf
