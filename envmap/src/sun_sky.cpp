#include "acdf/envmap/sun_sky.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "acdf/envmap/lat_long.h"

namespace acdf {

namespace {

struct Preset {
  const char* name;
  SunSkyParameters parameters;
};

const Preset kPresets[] = {
    {"noon", SunSkyParameters{}},
    {"afternoon", SunSkyParameters{.sunElevationDeg = 25,
                                   .sunAzimuthDeg = 200,
                                   .sunIntensity = 5e4,
                                   .zenith = {0.35f, 0.5f, 0.9f},
                                   .horizon = {0.9f, 0.9f, 0.95f},
                                   .glow = 0.8,
                                   .glowWidthDeg = 20}},
    {"sunset", SunSkyParameters{.sunElevationDeg = 2,
                                .sunAzimuthDeg = 270,
                                .sunRadiusDeg = 0.4,
                                .sunIntensity = 5e3,
                                .sunColor = {1.0f, 0.45f, 0.15f},
                                .zenith = {0.08f, 0.1f, 0.25f},
                                .horizon = {1.0f, 0.55f, 0.3f},
                                .gradient = 0.3,
                                .glow = 2.0,
                                .glowWidthDeg = 12,
                                .ground = {0.04f, 0.03f, 0.03f}}},
    {"overcast", SunSkyParameters{.sunRadiusDeg = 0,
                                  .sunIntensity = 0,
                                  .zenith = {0.9f, 0.9f, 0.92f},
                                  .horizon = {0.3f, 0.3f, 0.31f},
                                  .gradient = 1.0,
                                  .glow = 0,
                                  .ground = {0.08f, 0.08f, 0.08f}}},
};

constexpr double kDegree = std::numbers::pi / 180.0;

Rgb mix(const Rgb& a, const Rgb& b, double t) {
  auto lerp = [t](float x, float y) { return static_cast<float>(x + (y - x) * t); };
  return {lerp(a.r, b.r), lerp(a.g, b.g), lerp(a.b, b.b)};
}

void validate(uint32_t width, uint32_t height, const SunSkyParameters& p) {
  if (width == 0 || height == 0) throw std::invalid_argument("sun and sky: the image must have pixels");
  auto nonNegative = [](const Rgb& c) { return c.r >= 0 && c.g >= 0 && c.b >= 0; };
  if (!(std::abs(p.sunElevationDeg) <= 90) || !std::isfinite(p.sunAzimuthDeg) || !(p.sunRadiusDeg >= 0) ||
      !(p.sunRadiusDeg < 90) || !(p.sunIntensity >= 0) || !std::isfinite(p.sunIntensity) || !(p.gradient > 0) ||
      !(p.glow >= 0) || !(p.glowWidthDeg > 0) || !nonNegative(p.sunColor) || !nonNegative(p.zenith) ||
      !nonNegative(p.horizon) || !nonNegative(p.ground))
    throw std::invalid_argument(
        "sun and sky: parameters out of range (elevation in [-90, 90] degrees, radius in [0, 90), intensity, "
        "glow and colours >= 0, gradient and glow width > 0)");
}

}  // namespace

std::vector<std::string> sunSkyPresetNames() {
  std::vector<std::string> names;
  for (const Preset& p : kPresets) names.emplace_back(p.name);
  return names;
}

SunSkyParameters sunSkyPreset(const std::string& name) {
  for (const Preset& p : kPresets)
    if (name == p.name) return p.parameters;
  throw std::invalid_argument("unknown sun-and-sky preset '" + name + "' (noon, afternoon, sunset or overcast)");
}

Image sunSkyImage(uint32_t width, uint32_t height, const SunSkyParameters& p) {
  validate(width, height, p);
  const LatLongMapping mapping(width, height);
  const Vec3d sun =
      LatLongMapping::direction(std::numbers::pi / 2 - p.sunElevationDeg * kDegree, p.sunAzimuthDeg * kDegree);
  const bool hasSun = p.sunRadiusDeg > 0 && p.sunIntensity > 0;
  const double cosSunRadius = std::cos(p.sunRadiusDeg * kDegree);
  // A pixel can touch the disk only if its centre is within the radius plus the pixel's extent
  // (at most a pixel's width in φ or height in θ, whichever is larger, times √2 for the diagonal).
  const double reach = p.sunRadiusDeg * kDegree +
                       std::numbers::sqrt2 * std::max(std::numbers::pi / height, 2 * std::numbers::pi / width);
  const double cosReach = std::cos(std::min(reach, std::numbers::pi));
  const double glowWidth = p.glowWidthDeg * kDegree;
  const Rgb sunRadiance{static_cast<float>(p.sunIntensity * p.sunColor.r),
                        static_cast<float>(p.sunIntensity * p.sunColor.g),
                        static_cast<float>(p.sunIntensity * p.sunColor.b)};

  auto skyOrGround = [&](const Vec3d& w) -> Rgb {
    if (w.y <= 0) return p.ground;
    const Rgb base = mix(p.horizon, p.zenith, std::pow(w.y, p.gradient));
    const double gamma = std::acos(std::clamp(dot(w, sun), -1.0, 1.0));
    const double g = p.glow * std::exp(-gamma / glowWidth);
    return {static_cast<float>(base.r + g * p.sunColor.r), static_cast<float>(base.g + g * p.sunColor.g),
            static_cast<float>(base.b + g * p.sunColor.b)};
  };

  Image image;
  image.width = width;
  image.height = height;
  image.channels = 3;
  image.fileChannels = 3;
  image.pixels.resize(std::size_t{width} * height * 3);
  tbb::parallel_for(uint32_t{0}, height, [&](uint32_t row) {
    for (uint32_t column = 0; column < width; ++column) {
      const PixelIndex pixel{row, column};
      const Vec3d centre = mapping.directionInPixel(pixel, 0.5, 0.5);
      Rgb L = skyOrGround(centre);
      if (hasSun && dot(centre, sun) >= cosReach) {
        // Fraction of the pixel's solid angle inside the disk, by a regular grid of points.
        uint32_t inside = 0;
        for (uint32_t i = 0; i < kSunSupersampling; ++i)
          for (uint32_t j = 0; j < kSunSupersampling; ++j)
            inside += dot(mapping.directionInPixel(pixel, (i + 0.5) / kSunSupersampling, (j + 0.5) / kSunSupersampling),
                          sun) >= cosSunRadius;
        L = mix(L, sunRadiance, static_cast<double>(inside) / (kSunSupersampling * kSunSupersampling));
      }
      float* out = &image.pixels[3 * (std::size_t{row} * width + column)];
      out[0] = L.r;
      out[1] = L.g;
      out[2] = L.b;
    }
  });
  return image;
}

}  // namespace acdf
