// acdf's OpenImageIO module (openimageio_module.h): the image formats other than OpenEXR.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <type_traits>

#include "openimageio_module.h"

namespace {

template <std::size_t N>
void copyText(const std::string& text, char (&out)[N]) {
  const std::size_t n = std::min(text.size(), N - 1);
  std::memcpy(out, text.data(), n);
  out[n] = '\0';
}

// OpenImageIO keeps unretrieved error messages (per thread) and prints them at exit: always
// collect them, also when they are not used.
std::string takeGlobalError() { return OIIO::geterror(); }

// Subimage 0, MIP level 0, every pixel converted to float; three or more channels are RGB (the
// first three), one or two gray (channel 0).
bool read(const char* path, AcdfImageRead& out) {
  auto input = OIIO::ImageInput::open(path);
  if (!input) {
    copyText("not an image OpenImageIO can read", out.what);
    copyText(takeGlobalError(), out.detail);
    return false;
  }
  // Errors from here on are attached to `input`; fetch them before it is destroyed.
  auto fail = [&](const std::string& what) {
    std::string detail = input->geterror();
    const std::string global = takeGlobalError();
    if (detail.empty()) detail = global;
    input->close();
    copyText(what, out.what);
    copyText(detail, out.detail);
    return false;
  };
  if (!input->seek_subimage(0, 0)) return fail("cannot read subimage 0, MIP level 0");
  const OIIO::ImageSpec spec = input->spec();
  copyText(input->format_name(), out.format);
  AcdfImageClaims claims{};
  claims.width = spec.width;
  claims.height = spec.height;
  claims.depth = spec.depth;
  claims.fileChannels = spec.nchannels;
  claims.channelsRead = spec.nchannels >= 3 ? 3 : 1;
  claims.bytesPerRow = static_cast<double>(spec.scanline_bytes(true));
  claims.bufferedRows = spec.tile_width > 0 ? spec.tile_height : kScanlinesPerConversion;
  char problem[512];
  float* pixels = out.prepare(out.image, &claims, problem, sizeof problem);
  if (!pixels) return fail(problem);
  if (!input->read_image(0, 0, 0, static_cast<int>(claims.channelsRead), OIIO::TypeDesc::FLOAT, pixels))
    return fail("cannot read the pixels");
  input->close();
  (void)input->geterror();
  (void)takeGlobalError();
  return true;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) bool acdf_read_with_openimageio(const char* path,
                                                                                  AcdfImageRead* out) {
  try {
    return read(path, *out);
  } catch (const std::exception& e) {
    copyText("cannot read the image", out->what);
    copyText(e.what(), out->detail);
    return false;
  }
}

static_assert(std::is_same_v<decltype(&acdf_read_with_openimageio), AcdfReadWithOpenImageIO>);
