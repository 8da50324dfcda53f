#pragma once
// Reading and writing images through OpenImageIO: the one place in the tree that opens an image
// file (the environment maps here, `acdf cdf-stats` for its luminance grids).
//
// Reading takes subimage 0 at MIP level 0, whatever the file's layout (scanline or tiled), pixel
// type (half, float, integer) or compression: OpenImageIO converts every pixel to float. Channels:
// three or more are read as RGB (the first three; alpha and the rest are ignored), one or two as
// gray (channel 0; the second is taken to be alpha). Pixel values are returned as stored —
// negative values included, since what they mean is the caller's business — but NaN and Inf are
// an error naming the file and the pixel, unless the caller asks to replace them.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "acdf/sampling/file_error.h"

namespace acdf {

struct Image {
  uint32_t width = 0, height = 0;
  uint32_t channels = 0;              // 3 (RGB) or 1 (gray)
  std::vector<float> pixels;          // height × width × channels, row 0 = the top scanline
  uint32_t fileChannels = 0;          // channels stored in the file
  std::string format;                 // OpenImageIO's format name, e.g. "openexr"
  std::size_t nonFiniteReplaced = 0;  // NaN / Inf channel values set to 0 (ImageReadOptions)
};

struct ImageReadOptions {
  // false: a NaN or Inf channel value is an error. true: it becomes 0 and is counted.
  bool replaceNonFinite = false;
};

// Throws FileError: missing file, not a regular file, not an image OpenImageIO reads, no
// pixels, a volume image, a read error (e.g. a truncated file), NaN / Inf (see above), or an
// image too large for memory.
Image readImage(const std::string& path, const ImageReadOptions& options = {});

// Writes a float OpenEXR file (ZIP compression) of `image` (1 or 3 channels, named Y or R, G, B).
// The pixels go to a temporary file next to `path`, renamed over it once complete: a failure
// leaves no partial file (an existing file stays as it was). Throws FileError.
void writeExr(const std::string& path, const Image& image);

// Writes an 8-bit PNG of `image`'s linear values, sRGB-encoded after clamping to [0, 1] (a
// preview: no tone mapping), with the same temporary file and rename. Throws FileError.
void writeSrgbPng(const std::string& path, const Image& image);

}  // namespace acdf
