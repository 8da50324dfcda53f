#pragma once
// Reading and writing images: the one place in the tree that opens an image file (the environment
// maps here, `acdf cdf-stats` for its luminance grids). OpenEXR files (recognised by content) are
// read and written through OpenEXR's own library in every build; other formats are read through
// OpenImageIO in a build with ACDF_WITH_OPENIMAGEIO (the default), and refused without it (the
// portable wheel's build). PNG previews are written with zlib.
//
// Reading takes subimage 0 (OpenEXR's part 0) at MIP level 0, whatever the file's layout (scanline
// or tiled), pixel type (half, float, integer, normalised to [0, 1]) or compression; every pixel
// is converted to float. Channels of an OpenEXR file: R, G and B are read as RGB (alpha and the
// rest are ignored), else Y, or the one channel of a single-channel file, as gray; other files
// are refused naming their channels. Other formats: three or more channels are read as RGB (the
// first three), one or two as gray (channel 0; the second is taken to be alpha). RGB is returned
// in linear Rec. 709 / D65: a file that declares other chromaticities (OpenEXR's attribute) is
// converted as Mitsuba 3 does (color_space.h); gray values are taken as luminance, as stored.
// Pixel values are otherwise returned as stored — negative values included, since what they mean
// is the caller's business — but NaN and Inf are an error naming the file and the pixel, unless
// the caller asks to replace them.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "acdf/envmap/color_space.h"
#include "acdf/sampling/file_error.h"

namespace acdf {

struct Image {
  uint32_t width = 0, height = 0;
  uint32_t channels = 0;              // 3 (RGB) or 1 (gray)
  std::vector<float> pixels;          // height × width × channels, row 0 = the top scanline
  uint32_t fileChannels = 0;          // channels stored in the file
  std::string format;                 // "openexr", or OpenImageIO's format name, e.g. "png"
  std::size_t nonFiniteReplaced = 0;  // NaN / Inf channel values set to 0 (ImageReadOptions)
  // The chromaticities the file declared, if any; `pixels` are Rec. 709 / D65 whatever they were.
  std::optional<Chromaticities> declaredChromaticities;
};

struct ImageReadOptions {
  // false: a NaN or Inf channel value is an error. true: it becomes 0 and is counted.
  bool replaceNonFinite = false;
};

// Throws FileError: missing file, not a regular file, not an image this build reads, no pixels, an
// OpenEXR file without the channels above, chromaticities that define no RGB space, a volume
// image, a read error (e.g. a truncated file), NaN / Inf (see above), or an image too large for
// memory.
Image readImage(const std::string& path, const ImageReadOptions& options = {});

// Writes a float OpenEXR file (ZIP compression) of `image` (1 or 3 channels, named Y or R, G, B).
// `pixelsIn`: the chromaticities the RGB values are expressed in, declared in the file (nothing is
// converted; none: Rec. 709 / D65, declared by omission). The pixels go to a temporary file next
// to `path`, renamed over it once complete: a failure leaves no partial file (an existing file
// stays as it was). Throws FileError.
void writeExr(const std::string& path, const Image& image, const std::optional<Chromaticities>& pixelsIn = {});

// Writes an 8-bit PNG of `image`'s linear values, sRGB-encoded after clamping to [0, 1] (a
// preview: no tone mapping), with the same temporary file and rename. Throws FileError.
void writeSrgbPng(const std::string& path, const Image& image);

}  // namespace acdf
