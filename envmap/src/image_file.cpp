#include "acdf/envmap/image_file.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <new>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStandardAttributes.h>
#include <ImfVersion.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <zlib.h>
#if ACDF_WITH_OPENIMAGEIO
#include <dlfcn.h>

#include <mutex>
#endif

#include "acdf/envmap/color_space.h"
#include "acdf/sampling/regular_file.h"
#include "acdf/sampling/write_atomically.h"
#include "openimageio_module.h"

namespace acdf {

namespace fs = std::filesystem;

namespace {

std::string withDetail(const std::string& what, const std::string& detail) {
  return detail.empty() ? what : what + " (" + detail + ")";
}

// The most float pixel bytes one byte of image file may decode to. Larger claims come from a
// corrupt header, and are refused before the pixels are allocated (a 317-byte PNG claiming
// 30000 × 30000 pixels made us allocate 10 GB before the read failed). Measured on constant
// 16384 × 8192 images: OpenEXR DWAB 32692:1, ZIP 1941:1, PNG 4100:1; deflate's limit (1032:1)
// on a 1-bit palette PNG gives 99000:1. 2^18 leaves a margin of 2.6 above that.
constexpr double kMaxDecodedBytesPerFileByte = 1 << 18;

// OpenImageIO converts pixels to float through a buffer of kScanlinesPerConversion scanlines in
// the file's own format (openimageio_module.h): a 557-byte EXR claiming 16777218 × 1 pixels made
// it allocate 8.6 GB (found by fuzz_image). That buffer is kept under 1 GiB: 256 scanlines of
// 65536 pixels × 16 float channels fit. OpenEXR files are refused by the same rule, so a file is
// accepted or refused alike whichever library reads it.
constexpr double kMaxConversionBufferBytes = double(1 << 30);

// What a header claims, checked the same way for every format before any pixel is decoded.
struct HeaderClaims {
  int64_t width = 0, height = 0, depth = 1;
  int64_t fileChannels = 0;
  uint32_t channelsRead = 0;  // 3 (RGB) or 1 (gray)
  double bytesPerRow = 0;     // in the file's own pixel types
  int bufferedRows = kScanlinesPerConversion;  // a tile's height for tiled files
};

// Sizes `image` as `claims` say, or returns why the file cannot be read.
std::optional<std::string> prepareImage(Image& image, const HeaderClaims& claims, const std::string& path) {
  if (claims.width <= 0 || claims.height <= 0 || claims.fileChannels <= 0)
    return fmt::format("image has no pixels ({} x {}, {} channels)", claims.width, claims.height, claims.fileChannels);
  if (claims.depth > 1) return fmt::format("volume images (depth {}) are not supported", claims.depth);
  const int bufferedRows = std::max(claims.bufferedRows, 1);
  const double conversionBytes = claims.bytesPerRow * bufferedRows;
  if (conversionBytes > kMaxConversionBufferBytes)
    return fmt::format("the header claims rows of {} pixels x {} channels, too wide to read ({:.3g} GB per {} rows); "
                       "the file is corrupt",
                       claims.width, claims.fileChannels, conversionBytes * 1e-9, bufferedRows);
  const double decodedBytes = double(claims.width) * double(claims.height) * claims.channelsRead * sizeof(float);
  const auto fileBytes = fs::file_size(path);
  if (decodedBytes > kMaxDecodedBytesPerFileByte * static_cast<double>(fileBytes))
    return fmt::format("the header claims {} x {} pixels ({:.3g} GB as float) from a file of {} bytes, more than any "
                       "image format compresses to; the file is corrupt",
                       claims.width, claims.height, decodedBytes * 1e-9, fileBytes);
  image.width = static_cast<uint32_t>(claims.width);
  image.height = static_cast<uint32_t>(claims.height);
  image.fileChannels = static_cast<uint32_t>(claims.fileChannels);
  image.channels = claims.channelsRead;
  try {
    image.pixels.resize(std::size_t{image.width} * image.height * image.channels);
  } catch (const std::bad_alloc&) {
    return fmt::format("image of {} x {} pixels is too large to load", claims.width, claims.height);
  }
  return std::nullopt;
}

// Keeps the chromaticities a file declares, or returns why they cannot be used.
std::optional<std::string> declareChromaticities(Image& image, const Chromaticities& declared) {
  if (const auto problem = chromaticitiesProblem(declared))
    return fmt::format("its chromaticities cannot be used: {} ({})", *problem, toString(declared));
  image.declaredChromaticities = declared;
  return std::nullopt;
}

// RGB triples converted in place by m (in double). A triple with a NaN or Inf is left as the file
// has it, for the check that follows to name; one that overflows float becomes Inf.
void convertRgb(std::vector<float>& rgb, const ColorMatrix& m) {
  for (std::size_t i = 0; i + 2 < rgb.size(); i += 3) {
    const double r = rgb[i], g = rgb[i + 1], b = rgb[i + 2];
    if (!std::isfinite(r + g + b)) continue;
    for (int k = 0; k < 3; ++k) rgb[i + k] = static_cast<float>(m[k][0] * r + m[k][1] * g + m[k][2] * b);
  }
}

// The pixels as read → Rec. 709, with NaN and Inf refused or replaced (image_file.h).
void finishPixels(const std::string& path, Image& image, const ImageReadOptions& options) {
  const bool converted = image.channels == 3 && image.declaredChromaticities &&
                         !sameChromaticities(*image.declaredChromaticities, kRec709);
  if (converted) convertRgb(image.pixels, rec709FromRgb(*image.declaredChromaticities));
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
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
}

bool startsWithOpenExrMagic(const std::string& path) {
  char magic[4] = {};
  std::ifstream file(path, std::ios::binary);
  return file.read(magic, sizeof magic) && Imf::isImfMagic(magic);
}

std::vector<std::string> channelNames(const Imf::ChannelList& channels) {
  std::vector<std::string> names;
  for (auto c = channels.begin(); c != channels.end(); ++c) names.emplace_back(c.name());
  return names;
}

// The channels read from an OpenEXR file: R, G, B when it has all three (any others, alpha
// included, are ignored), else Y, else its one channel. Empty: none of these.
std::vector<std::string> openExrChannelsRead(const Imf::ChannelList& channels) {
  if (channels.findChannel("R") && channels.findChannel("G") && channels.findChannel("B")) return {"R", "G", "B"};
  if (channels.findChannel("Y")) return {"Y"};
  std::vector<std::string> all = channelNames(channels);
  return all.size() == 1 ? all : std::vector<std::string>{};
}

double pixelTypeBytes(Imf::PixelType type) { return type == Imf::HALF ? 2 : 4; }

// Subimage 0 (OpenEXR's part 0) at level 0, through OpenEXR's own library: every compression,
// scanline or tiled, half, float or uint channels (uint normalised by 2^32 − 1, as OpenImageIO
// converts them). Reading multipart, deep and subsampled files is OpenEXR's to refuse or not.
Image readOpenExr(const std::string& path) {
  Image image;
  image.format = "openexr";
  std::unique_ptr<Imf::InputFile> file;
  try {
    file = std::make_unique<Imf::InputFile>(path.c_str());
  } catch (const std::exception& e) {
    throw FileError(path, withDetail("OpenEXR cannot read it", oneLine(e.what())));
  }
  const Imf::Header& header = file->header();
  const Imath::Box2i window = header.dataWindow();
  const std::vector<std::string> names = openExrChannelsRead(header.channels());
  if (names.empty())
    throw FileError(path, fmt::format("no R, G, B or Y channel to read (channels: {})",
                                      fmt::join(channelNames(header.channels()), ", ")));
  HeaderClaims claims;
  claims.width = int64_t{window.max.x} - window.min.x + 1;
  claims.height = int64_t{window.max.y} - window.min.y + 1;
  claims.channelsRead = static_cast<uint32_t>(names.size());
  for (auto c = header.channels().begin(); c != header.channels().end(); ++c) {
    ++claims.fileChannels;
    claims.bytesPerRow += pixelTypeBytes(c.channel().type) * static_cast<double>(claims.width);
  }
  if (header.hasTileDescription()) claims.bufferedRows = static_cast<int>(header.tileDescription().ySize);
  if (Imf::hasChromaticities(header)) {
    const Imf::Chromaticities& c = Imf::chromaticities(header);
    const Chromaticities declared{{c.red.x, c.red.y}, {c.green.x, c.green.y}, {c.blue.x, c.blue.y},
                                  {c.white.x, c.white.y}};
    if (const auto problem = declareChromaticities(image, declared)) throw FileError(path, *problem);
  }
  if (const auto problem = prepareImage(image, claims, path)) throw FileError(path, *problem);

  const std::size_t xStride = sizeof(float) * image.channels;
  Imf::FrameBuffer frame;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const Imf::Channel& channel = header.channels()[names[k]];
    if (channel.xSampling != 1 || channel.ySampling != 1)
      throw FileError(path, fmt::format("channel {} is subsampled, which is not supported", names[k]));
    frame.insert(names[k], Imf::Slice::Make(Imf::FLOAT, image.pixels.data() + k, window, xStride));
  }
  try {
    file->setFrameBuffer(frame);
    file->readPixels(window.min.y, window.max.y);
  } catch (const std::exception& e) {
    throw FileError(path, withDetail("cannot read the pixels", oneLine(e.what())));
  }
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (header.channels()[names[k]].type != Imf::UINT) continue;
    for (std::size_t i = k; i < image.pixels.size(); i += image.channels) image.pixels[i] /= 4294967295.0f;
  }
  return image;
}

#if ACDF_WITH_OPENIMAGEIO
// The OpenImageIO module, loaded once, from the build tree or where it is installed; null with the
// loader's reason when neither is there.
AcdfReadWithOpenImageIO openImageIoModule(std::string& problem) {
  static std::once_flag loaded;
  static AcdfReadWithOpenImageIO entry = nullptr;
  static std::string failure;
  std::call_once(loaded, [] {
    for (const char* path : {ACDF_OPENIMAGEIO_MODULE_BUILT, ACDF_OPENIMAGEIO_MODULE_INSTALLED}) {
      if (void* module = dlopen(path, RTLD_NOW | RTLD_LOCAL)) {
        entry = reinterpret_cast<AcdfReadWithOpenImageIO>(dlsym(module, kAcdfReadWithOpenImageIO));
        if (entry) return;
      }
      const char* error = dlerror();
      failure = error ? oneLine(error) : std::string(path) + ": no entry point";
    }
  });
  problem = failure;
  return entry;
}

// Any other format OpenImageIO reads, through the module.
Image readWithOpenImageIO(const std::string& path) {
  std::string problem;
  const AcdfReadWithOpenImageIO read = openImageIoModule(problem);
  if (!read)
    throw FileError(path, withDetail("not an OpenEXR file, and acdf's OpenImageIO module cannot be loaded", problem));
  struct Target {
    Image image;
    const std::string& path;
  } target{Image{}, path};
  AcdfImageRead request{};
  request.image = &target;
  request.prepare = [](void* opaque, const AcdfImageClaims* c, char* reason, std::size_t size) -> float* {
    auto& [image, file] = *static_cast<Target*>(opaque);
    std::string why;
    try {
      const HeaderClaims claims{c->width, c->height, c->depth, c->fileChannels, c->channelsRead, c->bytesPerRow,
                                c->bufferedRows};
      if (const auto found = prepareImage(image, claims, file)) why = *found;
    } catch (const std::exception& e) {
      why = oneLine(e.what());
    }
    if (why.empty()) return image.pixels.data();
    const std::size_t n = std::min(why.size(), size - 1);
    std::copy_n(why.data(), n, reason);
    reason[n] = '\0';
    return nullptr;
  };
  if (!read(path.c_str(), &request)) throw FileError(path, withDetail(request.what, oneLine(request.detail)));
  target.image.format = request.format;
  return std::move(target.image);
}
#endif

}  // namespace

Image readImage(const std::string& path, const ImageReadOptions& options) {
  if (const auto problem = regularFileProblem(path)) throw FileError(path, *problem);
  Image image;
  if (startsWithOpenExrMagic(path)) {
    image = readOpenExr(path);
  } else {
#if ACDF_WITH_OPENIMAGEIO
    image = readWithOpenImageIO(path);
#else
    throw FileError(path, "not an OpenEXR file, and this build reads OpenEXR only (acdf built without OpenImageIO)");
#endif
  }
  finishPixels(path, image, options);
  return image;
}

namespace {

void checkWritable(const std::string& path, const Image& image) {
  if (image.channels != 1 && image.channels != 3)
    throw FileError(path, fmt::format("cannot write {} channels (1 or 3 expected)", image.channels));
  if (image.pixels.size() != std::size_t{image.width} * image.height * image.channels || image.pixels.empty())
    throw FileError(path, "pixel count does not match the image size");
}

// A PNG of 8-bit rows (gray or RGB, unfiltered) deflated by zlib, declared sRGB (ISO 15948).
std::string encodePng(const std::string& path, const Image& image, const std::vector<unsigned char>& bytes) {
  const std::size_t rowBytes = std::size_t{image.width} * image.channels;
  std::string rows;
  rows.reserve(image.height * (rowBytes + 1));
  for (uint32_t y = 0; y < image.height; ++y) {
    rows.push_back('\0');  // filter type 0: the row as it is
    rows.append(reinterpret_cast<const char*>(bytes.data()) + y * rowBytes, rowBytes);
  }
  uLongf deflatedBytes = compressBound(static_cast<uLong>(rows.size()));
  std::string deflated(deflatedBytes, '\0');
  if (compress2(reinterpret_cast<Bytef*>(deflated.data()), &deflatedBytes, reinterpret_cast<const Bytef*>(rows.data()),
                static_cast<uLong>(rows.size()), Z_DEFAULT_COMPRESSION) != Z_OK)
    throw FileError(path, "zlib cannot compress the pixels");
  deflated.resize(deflatedBytes);

  std::string png("\x89PNG\r\n\x1a\n", 8);
  auto bigEndian = [](uint32_t v) {
    return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
  };
  auto chunk = [&](const char* type, const std::string& data) {
    const std::string body = type + data;
    png += bigEndian(static_cast<uint32_t>(data.size())) + body;
    png += bigEndian(static_cast<uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(body.data()), body.size())));
  };
  const char colourType = image.channels == 3 ? 2 : 0;
  // Bit depth 8, the colour type, deflate, adaptive filtering, no interlace.
  chunk("IHDR", bigEndian(image.width) + bigEndian(image.height) + std::string{8, colourType, 0, 0, 0});
  chunk("sRGB", std::string(1, '\0'));  // perceptual rendering intent
  chunk("IDAT", deflated);
  chunk("IEND", "");
  return png;
}

}  // namespace

void writeExr(const std::string& path, const Image& image, const std::optional<Chromaticities>& pixelsIn) {
  checkWritable(path, image);
  if (pixelsIn)
    if (const auto problem = chromaticitiesProblem(*pixelsIn))
      throw FileError(path, "cannot declare chromaticities: " + *problem);
  Imf::Header header(static_cast<int>(image.width), static_cast<int>(image.height));
  header.compression() = Imf::ZIP_COMPRESSION;
  if (pixelsIn) {
    auto xy = [](const Chromaticities::Xy& c) { return Imath::V2f(float(c[0]), float(c[1])); };
    Imf::addChromaticities(header, {xy(pixelsIn->red), xy(pixelsIn->green), xy(pixelsIn->blue), xy(pixelsIn->white)});
  }
  const std::vector<const char*> names = image.channels == 1 ? std::vector{"Y"} : std::vector{"R", "G", "B"};
  Imf::FrameBuffer frame;
  for (std::size_t k = 0; k < names.size(); ++k) {
    header.channels().insert(names[k], Imf::Channel(Imf::FLOAT));
    frame.insert(names[k], Imf::Slice::Make(Imf::FLOAT, image.pixels.data() + k, header.dataWindow(),
                                            sizeof(float) * image.channels));
  }
  writeFileAtomically(path, [&](const std::string& temp) {
    std::unique_ptr<Imf::OutputFile> output;
    try {
      output = std::make_unique<Imf::OutputFile>(temp.c_str(), header);
    } catch (const std::exception& e) {
      throw FileError(path, withDetail("cannot create the temporary file " + temp, oneLine(e.what())));
    }
    try {
      output->setFrameBuffer(frame);
      output->writePixels(static_cast<int>(image.height));
    } catch (const std::exception& e) {
      throw FileError(path, withDetail("cannot write the temporary file " + temp, oneLine(e.what())));
    }
  });
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
  const std::string png = encodePng(path, image, bytes);
  writeFileAtomically(path, std::string_view(png));
}

}  // namespace acdf
