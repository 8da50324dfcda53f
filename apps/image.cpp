#include "image.h"

#include <cmath>
#include <limits>
#include <new>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "errors.h"
#include "files.h"

namespace acdf::app {

namespace {

// OpenImageIO keeps unretrieved error messages and prints them at exit; always collect them.
std::string takeGlobalError() { return oneLine(OIIO::geterror()); }

std::string withDetail(const std::string& what, const std::string& detail) {
  return detail.empty() ? what : what + " (" + detail + ")";
}

}  // namespace

LuminanceImage readLuminanceImage(const std::string& path) {
  checkInputFile(path);

  auto input = OIIO::ImageInput::open(path);
  if (!input) {
    const std::string detail = takeGlobalError();
    throw InputError(path, withDetail("not an image OpenImageIO can read", detail));
  }
  // Errors from here on are attached to `input`; fetch them before it is destroyed.
  auto fail = [&](const std::string& what) {
    std::string detail = oneLine(input->geterror());
    const std::string global = takeGlobalError();
    if (detail.empty()) detail = global;
    input->close();
    throw InputError(path, withDetail(what, detail));
  };

  if (!input->seek_subimage(0, 0)) fail("cannot read subimage 0, MIP level 0");
  const OIIO::ImageSpec spec = input->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    fail(fmt::format("image has no pixels ({} x {}, {} channels)", spec.width, spec.height, spec.nchannels));
  if (spec.depth > 1) fail(fmt::format("volume images (depth {}) are not supported", spec.depth));

  LuminanceImage image;
  image.width = static_cast<std::size_t>(spec.width);
  image.height = static_cast<std::size_t>(spec.height);
  image.channels = static_cast<std::size_t>(spec.nchannels);
  image.format = input->format_name();
  const int used = spec.nchannels >= 3 ? 3 : 1;
  const std::size_t pixels = image.width * image.height;

  std::vector<float> pixelsRgb;
  try {
    pixelsRgb.resize(pixels * static_cast<std::size_t>(used));
    image.values.reserve(pixels);
  } catch (const std::bad_alloc&) {
    fail(fmt::format("image of {} x {} pixels is too large to load", spec.width, spec.height));
  }
  if (!input->read_image(0, 0, 0, used, OIIO::TypeDesc::FLOAT, pixelsRgb.data()))
    fail("cannot read the pixels");
  input->close();
  (void)input->geterror();
  (void)takeGlobalError();

  image.values.resize(pixels);
  static const char* const kChannelNames[3] = {"R", "G", "B"};
  for (std::size_t i = 0; i < pixels; ++i) {
    const float* p = &pixelsRgb[i * static_cast<std::size_t>(used)];
    for (int c = 0; c < used; ++c) {
      if (!std::isfinite(p[c])) {
        const std::string channel = used == 3 ? kChannelNames[c] : "0";
        throw InputError(path, fmt::format("pixel (x {}, y {}) has channel {} = {}; NaN and Inf are not "
                                           "allowed", i % image.width, i / image.width, channel, p[c]));
      }
    }
    bool negativeChannel = false;
    for (int c = 0; c < used; ++c) negativeChannel = negativeChannel || p[c] < 0;
    if (negativeChannel) ++image.negativeChannelPixels;
    double lum = used == 3 ? 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2] : double(p[0]);
    if (lum < 0) {
      lum = 0;
      ++image.negativeClamped;
    }
    // Three finite floats cannot sum beyond the float range by more than the weights allow, but be
    // exact about it: the engine must see finite values.
    if (lum > std::numeric_limits<float>::max())
      throw InputError(path, fmt::format("pixel (x {}, y {}) has luminance {:g}, beyond the float range",
                                         i % image.width, i / image.width, lum));
    image.values[i] = static_cast<float>(lum);
  }
  return image;
}

}  // namespace acdf::app
