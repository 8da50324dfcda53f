#include "image.h"

#include <limits>

#include <fmt/format.h>

#include "acdf/envmap/image_file.h"
#include "errors.h"
#include "files.h"

namespace acdf::app {

namespace {

Image readCheckedImage(const std::string& path, const ImageReadOptions& options) {
  checkInputFile(path);
  return readImage(path, options);
}

}  // namespace

LuminanceImage readLuminanceImage(const std::string& path) {
  const Image raw = readCheckedImage(path, {});
  LuminanceImage image;
  image.width = raw.width;
  image.height = raw.height;
  image.channels = raw.fileChannels;
  image.format = raw.format;
  const std::size_t pixels = image.width * image.height;
  image.values.resize(pixels);
  for (std::size_t i = 0; i < pixels; ++i) {
    const float* p = &raw.pixels[i * raw.channels];
    bool negativeChannel = false;
    for (uint32_t c = 0; c < raw.channels; ++c) negativeChannel = negativeChannel || p[c] < 0;
    if (negativeChannel) ++image.negativeChannelPixels;
    double lum = raw.channels == 3 ? 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2] : double(p[0]);
    if (lum < 0) {
      lum = 0;
      ++image.negativeClamped;
    }
    // Three finite floats cannot sum beyond the float range by more than the weights allow, but be
    // exact about it: the engine must see finite values.
    if (lum > std::numeric_limits<float>::max())
      throw FileError(path, fmt::format("pixel (x {}, y {}) has luminance {:g}, beyond the float range",
                                        i % image.width, i / image.width, lum));
    image.values[i] = static_cast<float>(lum);
  }
  return image;
}

std::shared_ptr<const EnvironmentMap> readEnvironmentMap(const std::string& path, bool replaceNonFinite) {
  const Image raw = readCheckedImage(path, {.replaceNonFinite = replaceNonFinite});
  return std::make_shared<const EnvironmentMap>(EnvironmentMap::fromImage(raw, path));
}

}  // namespace acdf::app
