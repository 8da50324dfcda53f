// Reading environment maps: every layout and pixel type OpenEXR offers, the channels read, dirty
// pixels (negative, NaN, Inf), black and tiny maps, broken files; writing EXR and PNG with
// temporary file + rename.

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/environment_map.h"
#include "acdf/envmap/image_file.h"
#include "app_test_util.h"
#include "envmap_test_util.h"

namespace {

using namespace acdf;
using acdf::apptest::TempDirTest;
using acdf::envmaptest::kLightContexts;
namespace fs = std::filesystem;

struct Layout {
  std::string name;
  int channels;
  OIIO::TypeDesc type;
  std::string compression;
  bool tiled;
  bool mipmapped;
  double tolerance;  // relative, of what is read back
};

void PrintTo(const Layout& l, std::ostream* os) { *os << l.name; }

// Pixel values with structure in every channel (so a channel or row mix-up shows).
float pattern(int x, int y, int c) { return 0.25f + 0.5f * x + 0.125f * y * y + 2.0f * c; }

// Writes an image with OpenImageIO as described; with `mipmapped`, a second level of constant 99
// (which must never be read).
void writeTestImage(const std::string& path, const Layout& l, int width, int height) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(width, height, l.channels, l.type);
  spec.attribute("compression", l.compression);
  if (l.tiled) spec.tile_width = spec.tile_height = 16;
  // OpenImageIO writes MIP levels only for a texture format, like the shared stage map has.
  if (l.mipmapped) spec.attribute("textureformat", "LatLong Environment");
  std::vector<float> pixels(std::size_t(width) * height * l.channels);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < l.channels; ++c) pixels[(std::size_t(y) * width + x) * l.channels + c] = pattern(x, y, c);
  ASSERT_TRUE(out->open(path, spec, OIIO::ImageOutput::Create)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data())) << out->geterror();
  if (l.mipmapped) {
    OIIO::ImageSpec level = spec;
    level.width = level.full_width = width / 2;
    level.height = level.full_height = height / 2;
    ASSERT_TRUE(out->open(path, level, OIIO::ImageOutput::AppendMIPLevel)) << out->geterror();
    std::vector<float> half(std::size_t(width / 2) * (height / 2) * l.channels, 99.0f);
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, half.data())) << out->geterror();
  }
  ASSERT_TRUE(out->close()) << out->geterror();
}

class ReadLayout : public TempDirTest, public ::testing::WithParamInterface<Layout> {};

TEST_P(ReadLayout, ReadsLevelZeroAsRgb) {
  const Layout& l = GetParam();
  const std::string file = path("map.exr");
  const int width = 32, height = 16;
  if (l.mipmapped) {
    auto probe = OIIO::ImageOutput::create(file);
    ASSERT_TRUE(probe && probe->supports("mipmap")) << "OpenEXR output without MIP maps";
  }
  writeTestImage(file, l, width, height);

  const EnvironmentMap map = EnvironmentMap::load(file);
  ASSERT_EQ(map.width(), uint32_t(width));
  ASSERT_EQ(map.height(), uint32_t(height));
  for (uint32_t y = 0; y < map.height(); ++y)
    for (uint32_t x = 0; x < map.width(); ++x) {
      const Rgb v = map.radiance(PixelIndex{y, x});
      const float expected[3] = {pattern(x, y, 0), pattern(x, y, l.channels >= 3 ? 1 : 0),
                                 pattern(x, y, l.channels >= 3 ? 2 : 0)};
      const float got[3] = {v.r, v.g, v.b};
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(got[c], expected[c], l.tolerance * expected[c]) << "pixel " << x << ", " << y << " channel " << c;
    }
  EXPECT_EQ(map.negativePixelsClamped(), 0u);
}

INSTANTIATE_TEST_SUITE_P(
    OpenExr, ReadLayout,
    ::testing::Values(Layout{"float_rgb_scanline_zip", 3, OIIO::TypeDesc::FLOAT, "zip", false, false, 0},
                      Layout{"half_rgb_tiled_mipmapped_zip", 3, OIIO::TypeDesc::HALF, "zip", true, true, 1e-3},
                      Layout{"half_rgba_scanline_piz", 4, OIIO::TypeDesc::HALF, "piz", false, false, 1e-3},
                      Layout{"float_rgb_scanline_dwab", 3, OIIO::TypeDesc::FLOAT, "dwab", false, false, 0.05},
                      Layout{"half_y_tiled_none", 1, OIIO::TypeDesc::HALF, "none", true, false, 1e-3},
                      Layout{"float_rgb_b44_half", 3, OIIO::TypeDesc::HALF, "b44", false, false, 0.05}),
    [](const auto& info) { return info.param.name; });

class ReadImage : public TempDirTest {
 protected:
  // A float RGB scanline EXR with the given pixels (width × height × 3).
  std::string writeRgb(const std::string& name, uint32_t width, uint32_t height, std::vector<float> rgb) {
    Image image;
    image.width = width;
    image.height = height;
    image.channels = 3;
    image.pixels = std::move(rgb);
    const std::string file = path(name);
    writeExr(file, image);
    return file;
  }
};

TEST_F(ReadImage, NegativeChannelsAreClampedAndCounted) {
  const std::string file = writeRgb("neg.exr", 2, 2, {1, -0.5f, 2, -1, -1, -1, 3, 3, 3, 0, 0, -1e-4f});
  const EnvironmentMap map = EnvironmentMap::load(file);
  EXPECT_EQ(map.negativePixelsClamped(), 3u);
  EXPECT_EQ(map.radiance(PixelIndex{0, 0}), (Rgb{1, 0, 2}));
  EXPECT_EQ(map.radiance(PixelIndex{0, 1}), (Rgb{0, 0, 0}));
  EXPECT_EQ(map.radiance(PixelIndex{1, 0}), (Rgb{3, 3, 3}));
  EXPECT_FALSE(map.isBlack());
}

TEST_F(ReadImage, NanAndInfAreErrorsNamingTheFileAndPixel) {
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    const std::string file = writeRgb("bad.exr", 3, 2, {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, bad, 1, 1, 1, 1});
    try {
      (void)EnvironmentMap::load(file);
      FAIL() << "no error for " << bad;
    } catch (const FileError& e) {
      EXPECT_EQ(e.file(), file);
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos);
      EXPECT_NE(e.problem().find("pixel (x 1, y 1) has channel G"), std::string::npos) << e.problem();
    }
  }
}

TEST_F(ReadImage, ReplaceNonFiniteSetsZeroAndCounts) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const std::string file = writeRgb("bad.exr", 2, 1, {nan, 1, 1, 2, -inf, inf});
  const EnvironmentMap map = EnvironmentMap::load(file, ImageReadOptions{.replaceNonFinite = true});
  EXPECT_EQ(map.nonFiniteReplaced(), 3u);
  EXPECT_EQ(map.radiance(PixelIndex{0, 0}), (Rgb{0, 1, 1}));
  EXPECT_EQ(map.radiance(PixelIndex{0, 1}), (Rgb{2, 0, 0}));
}

TEST_F(ReadImage, AllBlackMapIsALightThatEmitsNothing) {
  const std::string file = writeRgb("black.exr", 8, 4, std::vector<float>(8 * 4 * 3, 0.0f));
  auto map = std::make_shared<const EnvironmentMap>(EnvironmentMap::load(file));
  EXPECT_TRUE(map->isBlack());
  for (EnvironmentSampling strategy : kEnvironmentSamplings) {
    const EnvironmentLight light(map, {.strategy = strategy});
    EXPECT_TRUE(light.emitsNothing());
    EXPECT_EQ(light.tableBytes(), 0u);
    for (const LightSampleContext& context : kLightContexts) {
      EXPECT_TRUE(light.table(context).pixelProbabilities().empty());
      const LightSample s = light.sample(context, 0.3f, 0.7f);
      EXPECT_EQ(s.pdf, 0.0);
      EXPECT_EQ(s.radiance, Rgb{});
      EXPECT_EQ(light.pdf(context, {0, 1, 0}), 0.0);
    }
    EXPECT_EQ(light.eval({0.3, -0.2, 0.9}), Rgb{});
  }
}

TEST_F(ReadImage, TinyMapsLoadAndSample) {
  for (auto [width, height] : {std::pair{1u, 1u}, std::pair{3u, 2u}}) {
    std::vector<float> rgb(std::size_t{width} * height * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = 0.5f + float(i);
    auto map = std::make_shared<const EnvironmentMap>(EnvironmentMap::load(writeRgb("tiny.exr", width, height, rgb)));
    ASSERT_EQ(map->width(), width);
    ASSERT_EQ(map->height(), height);
    for (EnvironmentSampling strategy : kEnvironmentSamplings) {
      const EnvironmentLight light(map, {.strategy = strategy});
      for (const LightSampleContext& context : kLightContexts)
        for (float u0 : {0.0f, 0.5f, kOneMinusEpsilon})
          for (float u1 : {0.0f, 0.5f, kOneMinusEpsilon}) {
            const LightSample s = light.sample(context, u0, u1);
            ASSERT_TRUE(s.pdf > 0 && std::isfinite(s.pdf)) << width << "x" << height << " " << toString(strategy);
            EXPECT_EQ(light.pdf(context, s.direction), s.pdf);
            EXPECT_EQ(light.eval(s.direction), s.radiance);
          }
    }
  }
}

TEST_F(ReadImage, BrokenFilesAreErrorsNamingTheFile) {
  // A truncated file: the first half of a valid one.
  const std::string whole = writeRgb("whole.exr", 64, 64, std::vector<float>(64 * 64 * 3, 1.0f));
  const std::string bytes = acdf::apptest::readFile(whole);
  const std::string truncated = path("truncated.exr");
  acdf::apptest::writeFile(truncated, bytes.substr(0, bytes.size() / 2));
  const std::string text = path("text.exr");
  acdf::apptest::writeFile(text, "this is not an image\n");
  const std::string empty = path("empty.exr");
  acdf::apptest::writeFile(empty, "");

  for (const auto& [file, needle] :
       {std::pair{truncated, std::string()}, std::pair{text, std::string()}, std::pair{empty, std::string()},
        std::pair{path("missing.exr"), std::string("no such file")},
        std::pair{dir_.string(), std::string("is a directory")}}) {
    try {
      (void)EnvironmentMap::load(file);
      FAIL() << "no error for " << file;
    } catch (const FileError& e) {
      EXPECT_EQ(e.file(), file);
      EXPECT_NE(e.problem().find(needle), std::string::npos) << e.problem();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  }
}

// Writes `spec` with every channel value = `value` (converted from float by OpenImageIO).
void writeConstantImage(const std::string& file, const OIIO::ImageSpec& spec, float value) {
  auto out = OIIO::ImageOutput::create(file);
  ASSERT_TRUE(out && out->open(file, spec)) << OIIO::geterror();
  const std::vector<float> pixels(std::size_t(spec.width) * spec.height * spec.nchannels, value);
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

// readImage(file) must throw an FileError naming file, whose one-line problem contains needle.
void expectReadError(const std::string& file, const std::string& needle) {
  try {
    (void)readImage(file);
    ADD_FAILURE() << "no error for " << file;
  } catch (const FileError& e) {
    EXPECT_EQ(e.file(), file);
    EXPECT_NE(e.problem().find(needle), std::string::npos) << e.problem();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
}

TEST_F(ReadImage, DeclaredChromaticitiesAreConvertedToRec709) {
  // ProPhoto RGB with its D50 white, as Photoshop saves maps: read as Rec. 709 / D65 through XYZ
  // (color_space.h), as Mitsuba 3 reads the same file; the declaration is kept for reports.
  const Chromaticities proPhoto{{0.7347, 0.2653}, {0.1596, 0.8404}, {0.0366, 0.0001}, {0.3457, 0.3585}};
  Image image;
  image.width = 3;
  image.height = 1;
  image.channels = 3;
  image.pixels = {1, 1, 1, 0.25f, 2, 0, 5, 0.5f, 0.125f};
  const std::string file = path("prophoto.exr");
  writeExr(file, image, proPhoto);
  const Image read = readImage(file);
  ASSERT_TRUE(read.declaredChromaticities);
  EXPECT_TRUE(sameChromaticities(*read.declaredChromaticities, proPhoto));
  const ColorMatrix m = rec709FromRgb(*read.declaredChromaticities);  // as stored: floats
  for (std::size_t p = 0; p < 3; ++p)
    for (int k = 0; k < 3; ++k) {
      const double want = m[k][0] * image.pixels[3 * p] + m[k][1] * image.pixels[3 * p + 1] +
                          m[k][2] * image.pixels[3 * p + 2];
      EXPECT_NEAR(read.pixels[3 * p + k], want, 1e-6 * std::abs(want) + 1e-7) << "pixel " << p << " channel " << k;
    }
  EXPECT_NEAR(read.pixels[0], 1.176464f, 1e-5);  // D50 white: no chromatic adaptation
  EXPECT_TRUE(EnvironmentMap::load(file).declaredChromaticities());
  // Declaring Rec. 709 changes nothing, bit for bit; declaring nothing is Rec. 709 too.
  writeExr(file, image, kRec709);
  EXPECT_EQ(readImage(file).pixels, image.pixels);
  writeExr(file, image);
  EXPECT_FALSE(readImage(file).declaredChromaticities);
  EXPECT_FALSE(EnvironmentMap::load(file).declaredChromaticities());
  // A value that overflows float in Rec. 709 is named like an Inf in the file.
  image.pixels[3] = 3e38f;
  writeExr(file, image, proPhoto);
  expectReadError(file, "pixel (x 1, y 0) has channel R = inf (in Rec. 709, from the declared chromaticities)");
}

TEST_F(ReadImage, ChromaticitiesThatDefineNoSpaceAreAnErrorNamingTheFile) {
  const std::string file = path("collinear.exr");
  OIIO::ImageSpec spec(4, 2, 3, OIIO::TypeDesc::FLOAT);
  const float collinear[8] = {0.64f, 0.33f, 0.395f, 0.195f, 0.15f, 0.06f, 0.3127f, 0.329f};
  spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), collinear);
  writeConstantImage(file, spec, 1.0f);
  expectReadError(file, "its chromaticities cannot be used: the red, green and blue chromaticities are collinear");
  // Nor are they written: no file is left.
  Image image;
  image.width = image.height = 1;
  image.channels = 3;
  image.pixels = {1, 1, 1};
  Chromaticities bad = kRec709;
  bad.white = {0.3, 0.0};
  EXPECT_THROW(writeExr(path("never.exr"), image, bad), FileError);
  EXPECT_FALSE(fs::exists(path("never.exr")));
}

// CRC-32 of PNG chunks (ISO 3309), bit by bit.
uint32_t pngCrc(const std::string& bytes) {
  uint32_t crc = 0xffffffffu;
  for (const unsigned char byte : bytes) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void putBigEndian(std::string& bytes, std::size_t at, uint32_t value) {
  for (int i = 0; i < 4; ++i) bytes[at + i] = static_cast<char>(value >> (24 - 8 * i));
}

TEST_F(ReadImage, HugeClaimedSizeIsRefusedBeforeAllocating) {
  // An 8 × 8 PNG whose header (with a valid CRC) then claims 30000 × 30000 pixels: 10.8 GB as
  // float, from a file of about 300 bytes. It used to be allocated before the read failed.
  const std::string small = path("small.png");
  writeConstantImage(small, OIIO::ImageSpec(8, 8, 3, OIIO::TypeDesc::UINT8), 0.5f);
  std::string bytes = acdf::apptest::readFile(small);
  const std::size_t ihdr = bytes.find("IHDR");
  ASSERT_NE(ihdr, std::string::npos);
  putBigEndian(bytes, ihdr + 4, 30000);
  putBigEndian(bytes, ihdr + 8, 30000);
  putBigEndian(bytes, ihdr + 17, pngCrc(bytes.substr(ihdr, 4 + 13)));
  const std::string huge = path("huge.png");
  acdf::apptest::writeFile(huge, bytes);
  expectReadError(huge, "claims 30000 x 30000 pixels (10.8 GB as float) from a file of");
  expectReadError(huge, "the file is corrupt");

  // The limit leaves room for real files that compress well: a constant 4096 × 2048 DWAB map
  // decodes to about 12000 times its size.
  const std::string constant = path("constant.exr");
  OIIO::ImageSpec dwab(4096, 2048, 3, OIIO::TypeDesc::HALF);
  dwab.attribute("compression", "dwab");
  writeConstantImage(constant, dwab, 0.5f);
  EXPECT_GT(4096.0 * 2048 * 3 * sizeof(float) / static_cast<double>(fs::file_size(constant)), 5000.0);
  EXPECT_EQ(readImage(constant).width, 4096u);
}

TEST_F(ReadImage, HugeScanlineIsRefusedBeforeOpenImageIOBuffersIt) {
  // A 2 × 2 half EXR (ZIP: one chunk) whose data window then claims one row of 16777218 pixels:
  // still one chunk, so OpenEXR opens it, and OpenImageIO would convert it through a buffer of
  // 256 such rows (8.6 GB). Found by fuzz_image.
  const std::string small = path("small.exr");
  OIIO::ImageSpec spec(2, 2, 1, OIIO::TypeDesc::HALF);
  spec.channelnames = {"Y"};
  spec.attribute("compression", "zip");
  writeConstantImage(small, spec, 0.5f);
  std::string bytes = acdf::apptest::readFile(small);
  const std::string attribute("dataWindow\0box2i\0", 17);
  const std::size_t window = bytes.find(attribute);
  ASSERT_NE(window, std::string::npos);
  const int32_t box[4] = {0, 0, 16777217, 0};  // xMin, yMin, xMax, yMax (inclusive), little-endian
  bytes.replace(window + attribute.size() + 4, sizeof box, reinterpret_cast<const char*>(box), sizeof box);
  const std::string wide = path("wide.exr");
  acdf::apptest::writeFile(wide, bytes);
  expectReadError(wide, "rows of 16777218 pixels x 1 channels, too wide");
}

TEST_F(ReadImage, WriteExrRoundTripsAndLeavesNoTemporary) {
  std::vector<float> rgb(5 * 3 * 3);
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = 0.1f * float(i);
  const std::string file = writeRgb("out.exr", 5, 3, rgb);
  const Image back = readImage(file);
  EXPECT_EQ(back.width, 5u);
  EXPECT_EQ(back.height, 3u);
  EXPECT_EQ(back.channels, 3u);
  EXPECT_EQ(back.pixels, rgb);
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir_)) files += entry.is_regular_file();
  EXPECT_EQ(files, 1u);

  Image image = back;
  EXPECT_THROW(writeExr(path("no/such/dir/out.exr"), image), FileError);
  EXPECT_FALSE(fs::exists(path("no")));
}

TEST_F(ReadImage, OpenExrChannelsAreRgbOrY) {
  // R, G, B in any order among others; Y with alpha; a single channel of any name.
  const struct {
    std::vector<std::string> names;
    std::vector<float> values;  // of the named channels, in that order
    std::vector<float> read;    // one pixel as read
  } cases[] = {{{"A", "B", "Z", "G", "R"}, {0.5f, 3, 9, 2, 1}, {1, 2, 3}},
               {{"A", "Y"}, {0.5f, 7}, {7}},
               {{"depth"}, {4}, {4}}};
  for (const auto& c : cases) {
    OIIO::ImageSpec spec(1, 1, static_cast<int>(c.names.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = c.names;
    const std::string file = path("channels.exr");
    auto out = OIIO::ImageOutput::create(file);
    ASSERT_TRUE(out && out->open(file, spec) && out->write_image(OIIO::TypeDesc::FLOAT, c.values.data()) &&
                out->close());
    EXPECT_EQ(readImage(file).pixels, c.read) << c.names.front();
  }
  OIIO::ImageSpec spec(2, 2, 2, OIIO::TypeDesc::HALF);
  spec.channelnames = {"Z", "A"};
  writeConstantImage(path("depth_alpha.exr"), spec, 1.0f);
  expectReadError(path("depth_alpha.exr"), "no R, G, B or Y channel to read (channels: A, Z)");
}

TEST_F(ReadImage, UnsignedIntegerChannelsAreNormalised) {
  OIIO::ImageSpec spec(2, 1, 3, OIIO::TypeDesc::UINT32);
  const std::string file = path("uint.exr");
  writeConstantImage(file, spec, 0.25f);
  for (float v : readImage(file).pixels) EXPECT_NEAR(v, 0.25f, 1e-7f);
}

TEST_F(ReadImage, SrgbPngIsReadBackAsWritten) {
  for (const uint32_t channels : {1u, 3u}) {
    Image image;
    image.width = 3;
    image.height = 2;
    image.channels = channels;
    for (uint32_t i = 0; i < image.width * image.height * channels; ++i) image.pixels.push_back(0.2f * float(i));
    const std::string file = path("preview.png");
    writeSrgbPng(file, image);
    const Image back = readImage(file);
    ASSERT_EQ(back.width, image.width);
    ASSERT_EQ(back.height, image.height);
    ASSERT_EQ(back.channels, channels);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
      const float v = std::min(image.pixels[i], 1.0f);
      const float encoded = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
      EXPECT_NEAR(back.pixels[i], std::lround(encoded * 255.0f) / 255.0f, 1e-6f) << channels << " channels, " << i;
    }
  }
}

TEST(SharedMaps, LoadWithTheirDirtOnBoard) {
  ACDF_SKIP_WITHOUT_SHARED_ENVMAPS();
  struct Expected {
    const char* name;
    uint32_t width, height;
  };
  for (const Expected& e : {Expected{"sunset_1024x512.exr", 1024, 512}, Expected{"forest_1024x512.exr", 1024, 512},
                            Expected{"stage_1000x500.exr", 1000, 500}}) {
    const std::string file = acdf::envmaptest::sharedEnvmap(e.name);
    const Image raw = readImage(file);
    const EnvironmentMap map = EnvironmentMap::fromImage(raw, file);
    EXPECT_EQ(map.width(), e.width) << e.name;
    EXPECT_EQ(map.height(), e.height) << e.name;
    EXPECT_FALSE(map.isBlack());
    // The negatives counted are exactly the pixels that had one.
    std::size_t negative = 0;
    for (std::size_t i = 0; i < raw.pixels.size(); i += 3)
      negative += raw.pixels[i] < 0 || raw.pixels[i + 1] < 0 || raw.pixels[i + 2] < 0;
    EXPECT_EQ(map.negativePixelsClamped(), negative) << e.name;
    if (std::string(e.name) == "forest_1024x512.exr") {
      EXPECT_GT(negative, 0u);
    }
  }
}

}  // namespace
