#include "input.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "acdf/sampling/grid_check.h"
#include "errors.h"
#include "files.h"
#include "image.h"
#include "npy.h"

namespace acdf::app {

namespace {

bool endsWithNpy(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".npy";
}

bool startsWithNpyMagic(const std::string& path) {
  unsigned char head[6] = {};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(head), sizeof(head));
  return in.gcount() == sizeof(head) && hasNpyMagic(head);
}

}  // namespace

const char* kindName(InputGrid::Kind kind) { return kind == InputGrid::Kind::Npy ? "npy" : "image"; }

InputGrid readInputGrid(const std::string& path) {
  checkInputFile(path);
  InputGrid grid;
  grid.path = path;
  if (endsWithNpy(path) || startsWithNpyMagic(path)) {
    NpyArray array = readNpy(path);
    grid.kind = InputGrid::Kind::Npy;
    grid.dims = std::move(array.shape);
    grid.values = std::move(array.values);
  } else {
    LuminanceImage image = readLuminanceImage(path);
    grid.kind = InputGrid::Kind::Image;
    grid.dims = {image.height, image.width};
    grid.values = std::move(image.values);
    grid.negativeClamped = image.negativeClamped;
    grid.negativeChannelPixels = image.negativeChannelPixels;
  }
  return grid;
}

std::vector<GridAxis> unitAxes(const InputGrid& grid) {
  std::vector<GridAxis> axes;
  axes.reserve(grid.dims.size());
  for (std::size_t d = 0; d < grid.dims.size(); ++d) {
    if (grid.dims[d] > std::numeric_limits<uint32_t>::max())
      throw FileError(grid.path, fmt::format("axis {} has {} cells, more than a grid axis can hold", d, grid.dims[d]));
    try {
      axes.emplace_back(static_cast<uint32_t>(grid.dims[d]), 0.0f, 1.0f);
    } catch (const std::invalid_argument& e) {
      throw FileError(grid.path, fmt::format("axis {} ({} cells over [0,1)): {}", d, grid.dims[d], e.what()));
    }
  }
  return axes;
}

void checkValues(const InputGrid& grid, const std::vector<GridAxis>& axes) {
  try {
    checkGridShape(grid.values.size(), axes);
    checkNonNegativeFinite(grid.values, axes);
  } catch (const std::invalid_argument& e) {
    throw FileError(grid.path, e.what());
  }
}

}  // namespace acdf::app
