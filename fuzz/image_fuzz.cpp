// Fuzzes the image reader (acdf/envmap/image_file.h) and what is built on it: the bytes go to a
// scratch file whose extension the first byte picks, then readImage(), and for a small image
// EnvironmentMap::fromImage() and an EnvironmentLight of each strategy. Bytes that start with
// OpenEXR's magic number go to OpenEXR's own reader whatever the extension (the .exr seeds), the
// others to OpenImageIO, which picks its format plugin by extension first, then by content.
// Invariants: readImage() returns an image of consistent size with finite pixels (converted from
// chromaticities that define an RGB space, when the file declares them), or throws
// FileError with a one-line message naming the file; the light's samples are unit
// directions with a finite pdf > 0 (a light that emits nothing returns pdf 0).

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/environment_map.h"
#include "acdf/envmap/image_file.h"
#include "fuzz_input.h"

namespace {

constexpr const char* kExtensions[] = {".exr", ".hdr", ".png", ".tif", ".ppm", ".tga", ".jpg", ""};
// Lights are built only for maps this small, so an execution stays fast.
constexpr std::size_t kMaxLightPixels = 64 * 64;

void checkLight(const std::shared_ptr<const acdf::EnvironmentMap>& map, acdf::EnvironmentSampling strategy) {
  using namespace acdf;
  const EnvironmentLight light(map, {.strategy = strategy});
  constexpr float kU[] = {0.0f, 0.25f, 0.5f, 0.999f, kOneMinusEpsilon};
  // Both kinds of call: a compensated light answers them from different tables.
  for (const LightSampleContext& context : {LightSampleContext{false}, LightSampleContext{true}}) {
    for (float u0 : kU) {
      for (float u1 : kU) {
        const LightSample s = light.sample(context, u0, u1);
        if (light.emitsNothing()) {
          fuzz::require(s.pdf == 0.0, "light: a black map returned a sample");
          continue;
        }
        const double length =
            std::sqrt(s.direction.x * s.direction.x + s.direction.y * s.direction.y + s.direction.z * s.direction.z);
        fuzz::require(std::fabs(length - 1.0) < 1e-5, "light: direction is not unit length");
        fuzz::require(std::isfinite(s.pdf) && s.pdf > 0.0, "light: pdf not finite and positive");
        const double pdf = light.pdf(context, s.direction);
        fuzz::require(std::isfinite(pdf) && pdf >= 0.0, "light: pdf(w) not finite");
      }
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace acdf;
  if (size == 0) return 0;
  const uint8_t mode = data[0];
  const fuzz::ScratchFile file(data + 1, size - 1, kExtensions[mode & 7]);
  Image image;
  try {
    image = readImage(file.path(), {.replaceNonFinite = (mode & 8) != 0});
  } catch (const FileError& e) {
    const std::string message = e.what();
    fuzz::require(message.rfind(file.path() + ": ", 0) == 0, "image: message does not name the file", message);
    return 0;
  }
  fuzz::require(image.width > 0 && image.height > 0, "image: no pixels");
  fuzz::require(image.channels == 1 || image.channels == 3, "image: channel count");
  fuzz::require(image.pixels.size() == std::size_t{image.width} * image.height * image.channels, "image: pixel count");
  for (float v : image.pixels) fuzz::require(std::isfinite(v), "image: non-finite pixel returned");
  if (image.declaredChromaticities)
    fuzz::require(!chromaticitiesProblem(*image.declaredChromaticities), "image: unusable chromaticities accepted");
  if (std::size_t{image.width} * image.height > kMaxLightPixels) return 0;

  const auto map = std::make_shared<const EnvironmentMap>(EnvironmentMap::fromImage(image, file.path()));
  for (auto strategy : {EnvironmentSampling::Uniform, EnvironmentSampling::Alias, EnvironmentSampling::Adaptive,
                        EnvironmentSampling::Compensated})
    checkLight(map, strategy);
  return 0;
}
