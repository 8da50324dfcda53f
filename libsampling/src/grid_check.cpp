#include "acdf/sampling/grid_check.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "acdf/sampling/sample.h"

namespace acdf {

namespace {

std::string cellName(std::size_t index, std::span<const GridAxis> axes) {
  if (axes.size() < 2) return {};
  std::string coords;
  for (std::size_t d = axes.size(); d-- > 0;) {
    coords = std::to_string(index % axes[d].cells()) + (coords.empty() ? "" : ", ") + coords;
    index /= axes[d].cells();
  }
  return " (cell [" + coords + "])";
}

}  // namespace

void checkNonNegativeFinite(std::span<const float> values, std::span<const GridAxis> axes) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    const float v = values[i];
    if (v >= 0.0f && v <= std::numeric_limits<float>::max()) continue;
    const char* what = std::isnan(v) ? "NaN" : std::isinf(v) ? "infinite" : "negative";
    throw std::invalid_argument("value at index " + std::to_string(i) + cellName(i, axes) + " is " + what + " (" +
                                std::to_string(v) + ")");
  }
}

void checkGridShape(std::size_t valueCount, std::span<const GridAxis> axes) {
  if (axes.empty() || axes.size() > kMaxDims) {
    throw std::invalid_argument("grid: needs 1 to " + std::to_string(kMaxDims) + " axes, got " +
                                std::to_string(axes.size()));
  }
  std::size_t cells = 1;
  for (const GridAxis& axis : axes) {
    if (cells > std::numeric_limits<std::size_t>::max() / axis.cells()) {
      throw std::invalid_argument("grid: the cell count overflows");
    }
    cells *= axis.cells();
  }
  if (cells != valueCount) {
    throw std::invalid_argument("grid: " + std::to_string(valueCount) + " values for a grid of " +
                                std::to_string(cells) + " cells");
  }
}

}  // namespace acdf
