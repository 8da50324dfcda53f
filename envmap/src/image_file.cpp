#include "acdf/envmap/image_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <new>
#include <system_error>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "acdf/envmap/color_space.h"
#include "acdf/sampling/regular_file.h"
#include "acdf/sampling/write_atomically.h"

namespace acdf {

namespace fs = std::filesystem;

namespace {

// OpenImageIO keeps unretrieved error messages (per thread) and prints them at exit: always
// collect them, also when they are not used. (Messages may span lines; the CLI folds them.)
std::string takeGlobalError() { return OIIO::geterror(); }

std::string withDetail(const std::string& what, const std::string& detail) {
  return detail.empty() ? what : what + " (" + detail + ")";
}

// The most float pixel bytes one byte of image file may decode to. Larger claims come from a
// corrupt header, and are refused before the pixels are allocated (a 317-byte PNG claiming
// 30000 × 30000 pixels made us allocate 10 GB before the read failed). Measured on constant
// 16384 × 8192 images: OpenEXR DWAB 32692:1, ZIP 1941:1, PNG 4100:1; deflate's limit (1032:1)
// on a 1-bit palette PNG gives 99000:1. 2^18 leaves a margin of 2.6 above that.
constexpr double kMaxDecodedBytesPerFileByte = 1 << 18;

// OpenImageIO 2.4 converts pixels to float through a buffer of whole scanlines in the file's own
// format, at least 256 of them even for a shorter image (ImageInput::read_scanlines), or one row
// of tiles: a 557-byte EXR claiming 16777218 × 1 pixels made it allocate 8.6 GB (found by
// fuzz_image). That buffer is kept under 1 GiB: 256 scanlines of 65536 pixels × 16 float
// channels fit.
constexpr double kMaxConversionBufferBytes = double(1 << 30);
constexpr int kScanlinesPerConversion = 256;

// RGB triples converted in place by m (in double). A triple with a NaN or Inf is left as the file
// has it, for the check that follows to name; one that overflows float becomes Inf.
void convertRgb(std::vector<float>& rgb, const ColorMatrix& m) {
  for (std::size_t i = 0; i + 2 < rgb.size(); i += 3) {
    const double r = rgb[i], g = rgb[i + 1], b = rgb[i + 2];
    if (!std::isfinite(r + g + b)) continue;
    for (int k = 0; k < 3; ++k) rgb[i + k] = static_cast<float>(m[k][0] * r + m[k][1] * g + m[k][2] * b);
  }
}

}  // namespace

Image readImage(const std::string& path, const ImageReadOptions& options) {
  if (const auto problem = regularFileProblem(path)) throw FileError(path, *problem);
  auto input = OIIO::ImageInput::open(path);
  if (!input) throw FileError(path, withDetail("not an image OpenImageIO can read", takeGlobalError()));
  // Errors from here on are attached to `input`; fetch them before it is destroyed.
  auto fail = [&](const std::string& what) {
    std::string detail = input->geterror();
    const std::string global = takeGlobalError();
    if (detail.empty()) detail = global;
    input->close();
    throw FileError(path, withDetail(what, detail));
  };

  if (!input->seek_subimage(0, 0)) fail("cannot read subimage 0, MIP level 0");
  const OIIO::ImageSpec spec = input->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    fail(fmt::format("image has no pixels ({} x {}, {} channels)", spec.width, spec.height, spec.nchannels));
  if (spec.depth > 1) fail(fmt::format("volume images (depth {}) are not supported", spec.depth));

  Image image;
  // OpenEXR's `chromaticities` (OpenImageIO gives it as 8 floats): red, green, blue, white xy.
  if (const OIIO::ParamValue* declared =
          spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8))) {
    const auto* v = static_cast<const float*>(declared->data());
    const Chromaticities c{{v[0], v[1]}, {v[2], v[3]}, {v[4], v[5]}, {v[6], v[7]}};
    if (const auto problem = chromaticitiesProblem(c))
      fail(fmt::format("its chromaticities cannot be used: {} ({})", *problem, toString(c)));
    image.declaredChromaticities = c;
  }
  image.width = static_cast<uint32_t>(spec.width);
  image.height = static_cast<uint32_t>(spec.height);
  image.fileChannels = static_cast<uint32_t>(spec.nchannels);
  image.channels = spec.nchannels >= 3 ? 3 : 1;
  image.format = input->format_name();
  const int bufferedRows = spec.tile_width > 0 ? spec.tile_height : kScanlinesPerConversion;
  const double conversionBytes = static_cast<double>(spec.scanline_bytes(true)) * std::max(bufferedRows, 1);
  if (conversionBytes > kMaxConversionBufferBytes)
    fail(
        fmt::format("the header claims rows of {} pixels x {} channels, too wide to read ({:.3g} GB per {} rows); "
                    "the file is corrupt",
                    spec.width, spec.nchannels, conversionBytes * 1e-9, std::max(bufferedRows, 1)));
  const std::size_t values = std::size_t{image.width} * image.height * image.channels;
  const double decodedBytes = static_cast<double>(values) * sizeof(float);
  const auto fileBytes = fs::file_size(path);
  if (decodedBytes > kMaxDecodedBytesPerFileByte * static_cast<double>(fileBytes))
    fail(
        fmt::format("the header claims {} x {} pixels ({:.3g} GB as float) from a file of {} bytes, more than any "
                    "image format compresses to; the file is corrupt",
                    spec.width, spec.height, decodedBytes * 1e-9, fileBytes));
  try {
    image.pixels.resize(values);
  } catch (const std::bad_alloc&) {
    fail(fmt::format("image of {} x {} pixels is too large to load", spec.width, spec.height));
  }
  if (!input->read_image(0, 0, 0, static_cast<int>(image.channels), OIIO::TypeDesc::FLOAT, image.pixels.data()))
    fail("cannot read the pixels");
  input->close();
  (void)input->geterror();
  (void)takeGlobalError();

  const bool converted = image.channels == 3 && image.declaredChromaticities &&
                         !sameChromaticities(*image.declaredChromaticities, kRec709);
  if (converted) convertRgb(image.pixels, rec709FromRgb(*image.declaredChromaticities));
  for (std::size_t i = 0; i < values; ++i) {
    float& v = image.pixels[i];
    if (std::isfinite(v)) continue;
    if (!options.replaceNonFinite) {
      static const char* const kRgb[3] = {"R", "G", "B"};
      const std::size_t pixel = i / image.channels;
      const std::string channel = image.channels == 3 ? kRgb[i % 3] : "0";
      throw FileError(path, fmt::format("pixel (x {}, y {}) has channel {} = {}{}; NaN and Inf are not allowed",
                                        pixel % image.width, pixel / image.width, channel, v,
                                        converted ? " (in Rec. 709, from the declared chromaticities)" : ""));
    }
    v = 0.0f;
    ++image.nonFiniteReplaced;
  }
  return image;
}

namespace {

void checkWritable(const std::string& path, const Image& image) {
  if (image.channels != 1 && image.channels != 3)
    throw FileError(path, fmt::format("cannot write {} channels (1 or 3 expected)", image.channels));
  if (image.pixels.size() != std::size_t{image.width} * image.height * image.channels || image.pixels.empty())
    throw FileError(path, "pixel count does not match the image size");
}

// Writes `pixels` (of `type`, image's size and channels) in OpenImageIO's `format` to a temporary
// file next to `path`, then renames it over `path`: a failure leaves no partial file.
void writeAtomically(const std::string& path, const char* format, const Image& image, OIIO::TypeDesc type,
                     const void* pixels, const char* compression, const std::optional<Chromaticities>& pixelsIn) {
  writeFileAtomically(path, [&](const std::string& temp) {
    auto output = OIIO::ImageOutput::create(format);
    if (!output)
      throw FileError(path, withDetail(fmt::format("OpenImageIO cannot write {}", format), takeGlobalError()));
    OIIO::ImageSpec spec(static_cast<int>(image.width), static_cast<int>(image.height),
                         static_cast<int>(image.channels), type);
    if (image.channels == 1) spec.channelnames = {"Y"};
    if (compression) spec.attribute("compression", compression);
    if (pixelsIn) {
      const float declared[8] = {float(pixelsIn->red[0]),   float(pixelsIn->red[1]),   float(pixelsIn->green[0]),
                                 float(pixelsIn->green[1]), float(pixelsIn->blue[0]),  float(pixelsIn->blue[1]),
                                 float(pixelsIn->white[0]), float(pixelsIn->white[1])};
      spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), declared);
    }
    auto fail = [&](const std::string& what) {
      const std::string detail = output->geterror();
      (void)takeGlobalError();
      output->close();
      throw FileError(path, withDetail(what, detail));
    };
    if (!output->open(temp, spec)) fail("cannot create the temporary file " + temp);
    if (!output->write_image(type, pixels)) fail("cannot write the temporary file " + temp);
    if (!output->close()) fail("cannot write the temporary file " + temp);
  });
}

}  // namespace

void writeExr(const std::string& path, const Image& image, const std::optional<Chromaticities>& pixelsIn) {
  checkWritable(path, image);
  if (pixelsIn)
    if (const auto problem = chromaticitiesProblem(*pixelsIn))
      throw FileError(path, "cannot declare chromaticities: " + *problem);
  writeAtomically(path, "openexr", image, OIIO::TypeDesc::FLOAT, image.pixels.data(), "zip", pixelsIn);
}

void writeSrgbPng(const std::string& path, const Image& image) {
  checkWritable(path, image);
  std::vector<unsigned char> bytes(image.pixels.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    const float v = std::clamp(std::isfinite(image.pixels[i]) ? image.pixels[i] : 0.0f, 0.0f, 1.0f);
    // The sRGB transfer function (IEC 61966-2-1).
    const float encoded = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
    bytes[i] = static_cast<unsigned char>(std::lround(encoded * 255.0f));
  }
  writeAtomically(path, "png", image, OIIO::TypeDesc::UINT8, bytes.data(), nullptr, std::nullopt);
}

}  // namespace acdf
