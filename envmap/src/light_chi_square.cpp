#include "acdf/envmap/light_chi_square.h"

#include <numeric>
#include <stdexcept>

#include "acdf/envmap/lat_long.h"

namespace acdf {

SphereChiSquareReport mapChiSquareTest(uint32_t width, uint32_t height, const DirectionSampler& mapSample,
                                       const DirectionPdf& mapPdf, const LightChiSquareOptions& options) {
  const uint32_t common = std::gcd(width, height);
  uint32_t k = 1;  // the smallest common divisor within the bin limit, else the largest
  for (uint32_t d = 1; d <= common; ++d) {
    if (common % d != 0) continue;
    k = d;
    if (uint64_t{width / d} * (height / d) <= kMaxLightChiSquareBins) break;
  }

  SphereChiSquareOptions o;
  o.samples = options.samples;
  o.seed = options.seed;
  o.alpha = options.alpha;
  o.thetaBins = height / k;
  o.phiBins = width / k;
  o.subPoints = k;
  return sphereChiSquareTest(
      [&](float u0, float u1) {
        const DirectionSample s = mapSample(u0, u1);
        return DirectionSample{LatLongMapping::toZUp(s.direction), s.pdf};
      },
      [&](const Vec3d& zUp) { return mapPdf(LatLongMapping::fromZUp(zUp)); }, o);
}

SphereChiSquareReport lightChiSquareTest(const EnvironmentLight& light, const LightChiSquareOptions& options) {
  if (light.emitsNothing()) throw std::invalid_argument("chi-square test: the light emits nothing to sample");
  const Rotation& worldFromMap = light.options().worldFromMap;
  return mapChiSquareTest(
      light.map().width(), light.map().height(),
      [&](float u0, float u1) {
        const LightSample s = light.sample(options.context, u0, u1);
        return DirectionSample{worldFromMap.applyInverse(s.direction), s.pdf};
      },
      [&](const Vec3d& w) { return light.pdf(options.context, worldFromMap.apply(w)); }, options);
}

}  // namespace acdf
