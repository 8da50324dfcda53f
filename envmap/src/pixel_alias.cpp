#include "acdf/envmap/pixel_alias.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace acdf {

namespace {

// Each row's sum of values, in double. The masses are only compared with one another: when a row's
// sum would overflow float (pixels near float's maximum), all are scaled down alike.
std::vector<float> rowMasses(std::span<const float> values, uint32_t width, uint32_t height) {
  if (values.size() != std::size_t{width} * height || values.empty())
    throw std::invalid_argument("PixelAlias: the values do not match width x height");
  std::vector<double> sums(height);
  for (uint32_t r = 0; r < height; ++r)
    for (float v : values.subspan(std::size_t{r} * width, width)) sums[r] += v;
  const double largest = *std::max_element(sums.begin(), sums.end());
  constexpr double kFloatMax = std::numeric_limits<float>::max();
  const double scale = largest > kFloatMax ? kFloatMax / largest : 1.0;
  std::vector<float> masses(height);
  for (uint32_t r = 0; r < height; ++r) masses[r] = static_cast<float>(sums[r] * scale);
  return masses;
}

}  // namespace

PixelAlias::PixelAlias(std::span<const float> values, uint32_t width, uint32_t height)
    : rows_(rowMasses(values, width, height)) {
  if (rows_.isUniformFallback()) throw std::invalid_argument("PixelAlias: all values are zero");
  columns_.reserve(height);
  for (uint32_t r = 0; r < height; ++r) columns_.emplace_back(values.subspan(std::size_t{r} * width, width));
}

PixelAlias::Pick PixelAlias::sample(float u0, float u1) const {
  const AliasTable::Discrete row = rows_.sample(u0);
  const AliasTable::Discrete column = columns_[row.index].sample(u1);
  const PixelIndex p{row.index, column.index};
  return {p, probability(p), row.remapped, column.remapped};
}

std::size_t PixelAlias::bytes() const {
  std::size_t total = rows_.bytes();
  for (const AliasTable& t : columns_) total += t.bytes();
  return total;
}

std::vector<double> PixelAlias::pixelProbabilities() const {
  std::vector<double> p;
  p.reserve(rows_.size() * columns_.front().size());
  for (uint32_t r = 0; r < rows_.size(); ++r)
    for (uint32_t c = 0; c < columns_[r].size(); ++c) p.push_back(probability({r, c}));
  return p;
}

}  // namespace acdf
