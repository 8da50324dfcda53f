#include "acdf/sampling/alias_grid.h"

#include <stdexcept>
#include <string>

#include "acdf/sampling/grid_check.h"

namespace acdf {

namespace {
std::span<const float> checked(std::span<const float> values, std::span<const GridAxis> axes) {
  checkGridShape(values.size(), axes);
  if (values.size() > (std::size_t{1} << 24)) {
    throw std::invalid_argument("alias grid: " + std::to_string(values.size()) +
                                " cells; a float variate reaches at most 2^24 table slots");
  }
  checkNonNegativeFinite(values, axes);
  return values;
}
}  // namespace

AliasGrid::AliasGrid(std::span<const float> values, std::vector<GridAxis> axes)
    : axes_(std::move(axes)), strides_(axes_.size(), 1), cellVolume_(1.0), table_(checked(values, axes_)) {
  for (std::size_t d = axes_.size() - 1; d-- > 0;) strides_[d] = strides_[d + 1] * axes_[d + 1].cells();
  for (const GridAxis& axis : axes_) cellVolume_ *= axis.cellWidth();
}

SampleND AliasGrid::sample(std::span<const float> u) const {
  if (u.size() != axes_.size()) {
    throw std::invalid_argument("alias grid: " + std::to_string(u.size()) + " variates for " +
                                std::to_string(axes_.size()) + " axes");
  }
  const bool twoVariates = axes_.size() >= 2;
  const AliasTable::Discrete cell = twoVariates ? table_.sample(u[0], u[1]) : table_.sample(u[0]);
  SampleND result;
  result.dims = static_cast<uint8_t>(axes_.size());
  std::size_t rest = cell.index;
  for (std::size_t d = 0; d < axes_.size(); ++d) {
    const auto index = static_cast<uint32_t>(rest / strides_[d]);
    rest %= strides_[d];
    float t = clampUnit(u[d]);
    if (d == 0) t = twoVariates ? table_.cellFraction(u[0]) : cell.remapped;
    if (d == 1) t = cell.remapped;
    result.x[d] = axes_[d].place(index, index + 1, t);
  }
  result.pdf = clampDensity(cell.probability / cellVolume_);
  return result;
}

float AliasGrid::pdf(std::span<const float> x) const {
  if (x.size() != axes_.size()) {
    throw std::invalid_argument("alias grid: " + std::to_string(x.size()) + " coordinates for " +
                                std::to_string(axes_.size()) + " axes");
  }
  std::size_t index = 0;
  for (std::size_t d = 0; d < axes_.size(); ++d) {
    if (!axes_[d].contains(x[d])) return 0.0f;
    index += axes_[d].cellOf(x[d]) * strides_[d];
  }
  return clampDensity(table_.probability(static_cast<uint32_t>(index)) / cellVolume_);
}

std::vector<double> AliasGrid::cellProbabilities() const {
  std::vector<double> p(table_.size());
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = table_.probability(static_cast<uint32_t>(i));
  return p;
}

}  // namespace acdf
