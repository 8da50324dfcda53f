#pragma once
// The chi-square goodness-of-fit test of an environment light's sampler against its own pdf: the
// spherical test of acdf/sampling/sphere_chi_square.h, with bins aligned to the map's pixels.
//
// Directions are turned back into the map frame (undoing the light's rotation) and then into
// sphere.h's z-up frame, where their (θ, φ) are the map's (lat_long.h). Each (θ, φ) bin is a
// k × k block of pixels (k the smallest common divisor of width and height that leaves at most
// kMaxLightChiSquareBins bins, or their greatest common divisor if none does), and the expected counts use k × k points
// per bin: one per pixel, so the midpoint rule is exact for the light's pdf, which is constant per pixel in solid
// angle.

#include <cstdint>

#include "acdf/envmap/environment_light.h"
#include "acdf/sampling/sphere_chi_square.h"

namespace acdf {

inline constexpr uint64_t kMaxLightChiSquareBins = 10'000;

struct LightChiSquareOptions {
  uint64_t samples = 1'000'000;
  uint64_t seed = 0x2545F4914F6CDD1DULL;
  double alpha = 0.01;  // level of this one test
  // The table the light's strategy names by default (compensated: the compensated one).
  LightSampleContext context{.allowIncompletePdf = true};
};

// The light must emit something (throws std::invalid_argument otherwise).
SphereChiSquareReport lightChiSquareTest(const EnvironmentLight& light, const LightChiSquareOptions& options = {});

// The same test of any sampler of a width × height map's directions, in the map frame (lat_long.h)
// (options.context is unused).
SphereChiSquareReport mapChiSquareTest(uint32_t width, uint32_t height, const DirectionSampler& mapSample,
                                       const DirectionPdf& mapPdf, const LightChiSquareOptions& options = {});

}  // namespace acdf
