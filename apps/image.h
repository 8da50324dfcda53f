#pragma once
// Images for the subcommands, read through the one image reader of the tree
// (acdf/envmap/image_file.h): as a 2D grid of luminance (cdf-stats) or as an environment map.
// Reader errors are FileError("<path>: <problem>").

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "acdf/envmap/environment_map.h"

namespace acdf::app {

struct LuminanceImage {
  std::size_t width = 0, height = 0;
  std::size_t channels = 0;               // channels in the file
  std::vector<float> values;              // height x width, row-major (row 0 = top scanline)
  std::size_t negativeClamped = 0;        // luminances < 0 that were set to 0
  std::size_t negativeChannelPixels = 0;  // pixels with a used channel < 0 (kept in the luminance)
  std::string format;                     // "openexr", or OpenImageIO's format name
};

// Subimage 0, MIP level 0. Luminance = 0.2126 R + 0.7152 G + 0.0722 B from the first three
// channels; an image with one or two channels (gray, gray + alpha) uses channel 0. Channels enter
// the luminance as they are (a slightly negative channel of a lossy file is counted, not changed);
// a negative luminance is clamped to 0 and counted; a NaN or Inf in a used channel is an error.
// Throws FileError("<path>: <problem>").
LuminanceImage readLuminanceImage(const std::string& path);

// EnvironmentMap::load (negative channels clamped and counted; NaN / Inf an error, or replaced
// with 0 and counted when replaceNonFinite). Throws FileError.
std::shared_ptr<const EnvironmentMap> readEnvironmentMap(const std::string& path, bool replaceNonFinite);

}  // namespace acdf::app
