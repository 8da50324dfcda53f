#include "acdf/envmap/light_chi_square.h"

#include <numeric>
#include <stdexcept>

#include "acdf/envmap/lat_long.h"

namespace acdf {

SphereChiSquareReport lightChiSquareTest(const EnvironmentLight& light, const LightChiSquareOptions& options) {
  if (light.emitsNothing()) throw std::invalid_argument("chi-square test: the light emits nothing to sample");
  const uint32_t width = light.map().width(), height = light.map().height();
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
  const Rotation& worldFromMap = light.options().worldFromMap;
  auto toTestFrame = [&](const Vec3d& world) { return LatLongMapping::toZUp(worldFromMap.applyInverse(world)); };
  auto fromTestFrame = [&](const Vec3d& zUp) { return worldFromMap.apply(LatLongMapping::fromZUp(zUp)); };
  return sphereChiSquareTest(
      [&](float u0, float u1) {
        const LightSample s = light.sample(options.context, u0, u1);
        return DirectionSample{toTestFrame(s.direction), s.pdf};
      },
      [&](const Vec3d& zUp) { return light.pdf(options.context, fromTestFrame(zUp)); }, o);
}

}  // namespace acdf
