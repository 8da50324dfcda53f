#include "acdf/envmap/environment_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace acdf {

EnvironmentMap::EnvironmentMap(uint32_t width, uint32_t height, std::vector<float> rgb)
    : mapping_((width == 0 || height == 0)
                   ? throw std::invalid_argument(fmt::format("EnvironmentMap: empty map ({} x {})", width, height))
                   : LatLongMapping(width, height)),
      rgb_(std::move(rgb)) {
  const std::size_t pixels = std::size_t{width} * height;
  if (rgb_.size() != 3 * pixels)
    throw std::invalid_argument(fmt::format("EnvironmentMap: {} values for {} x {} RGB pixels (expected {})",
                                            rgb_.size(), width, height, 3 * pixels));
  for (std::size_t i = 0; i < pixels; ++i) {
    bool negative = false;
    for (std::size_t c = 0; c < 3; ++c) {
      float& v = rgb_[3 * i + c];
      if (!std::isfinite(v))
        throw std::invalid_argument(
            fmt::format("EnvironmentMap: pixel (x {}, y {}) has channel {} = {}; NaN and "
                        "Inf are not allowed",
                        i % width, i / width, "RGB"[c], v));
      if (v < 0.0f) {
        v = 0.0f;
        negative = true;
      }
      if (v > 0.0f) black_ = false;
    }
    negativePixelsClamped_ += negative;
  }
}

EnvironmentMap EnvironmentMap::fromImage(const Image& image, const std::string& path) {
  std::vector<float> rgb;
  if (image.channels == 3) {
    rgb = image.pixels;
  } else {
    rgb.resize(3 * image.pixels.size());
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
      rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = image.pixels[i];
  }
  try {
    EnvironmentMap map(image.width, image.height, std::move(rgb));
    map.nonFiniteReplaced_ = image.nonFiniteReplaced;
    map.declaredChromaticities_ = image.declaredChromaticities;
    return map;
  } catch (const std::invalid_argument& e) {
    throw FileError(path, e.what());
  }
}

EnvironmentMap EnvironmentMap::load(const std::string& path, const ImageReadOptions& options) {
  return fromImage(readImage(path, options), path);
}

std::vector<float> EnvironmentMap::pixelPower() const {
  std::vector<float> power(std::size_t{width()} * height());
  for (uint32_t r = 0; r < height(); ++r) {
    const double solidAngle = mapping_.pixelSolidAngle(r);
    for (uint32_t c = 0; c < width(); ++c) {
      const std::size_t i = std::size_t{r} * width() + c;
      const double luminance = Rgb{rgb_[3 * i], rgb_[3 * i + 1], rgb_[3 * i + 2]}.luminance();
      // A 1×1 map's pixel covers 4π: keep the product of a huge radiance finite.
      power[i] = static_cast<float>(std::min(luminance * solidAngle, double{std::numeric_limits<float>::max()}));
    }
  }
  return power;
}

double EnvironmentMap::luminanceIntegral() const {
  double sum = 0;
  for (float p : pixelPower()) sum += p;
  return sum;
}

}  // namespace acdf
