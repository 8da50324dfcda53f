#pragma once
// The tabulated function a subcommand works on, read from a .npy array or an image.

#include <cstddef>
#include <string>
#include <vector>

#include "acdf/sampling/grid_axis.h"

namespace acdf::app {

struct InputGrid {
  enum class Kind { Npy, Image };
  Kind kind = Kind::Npy;
  std::string path;
  std::vector<std::size_t> dims;          // sizes, axis 0 slowest (images: height, width)
  std::vector<float> values;              // row-major, product(dims) entries
  std::size_t negativeClamped = 0;        // images only: negative luminances set to 0
  std::size_t negativeChannelPixels = 0;  // images only: pixels with a negative channel (informative)
};

// A file starting with the .npy magic string (or named *.npy) is read as .npy, anything else
// as an image (acdf/envmap/image_file.h). Throws FileError. Values of a .npy file are not checked here.
InputGrid readInputGrid(const std::string& path);

// One GridAxis(size, 0, 1) per dimension. Throws FileError (naming the axis) when the engine
// cannot represent an axis, e.g. more cells than [0,1) in float can hold.
std::vector<GridAxis> unitAxes(const InputGrid& grid);

// acdf::checkNonNegativeFinite on the values, its message rethrown as FileError for the file.
void checkValues(const InputGrid& grid, const std::vector<GridAxis>& axes);

const char* kindName(InputGrid::Kind kind);

}  // namespace acdf::app
