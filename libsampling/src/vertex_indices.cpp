#include "acdf/sampling/vertex_indices.h"

#include <algorithm>

namespace acdf {

void VertexIndices::append(const VertexIndices& other) {
  if (wide_ == other.wide_) {
    narrow16_.insert(narrow16_.end(), other.narrow16_.begin(), other.narrow16_.end());
    wide32_.insert(wide32_.end(), other.wide32_.begin(), other.wide32_.end());
    return;
  }
  for (std::size_t i = 0; i < other.size(); ++i) push_back(other[i]);
}

std::size_t VertexIndices::intervalOf(std::size_t first, std::size_t last, uint32_t cell) const {
  // Largest j with v[j] <= cell, kept below last-1 so [v[j], v[j+1]) is an interval.
  auto search = [&](const auto& v) {
    auto it = std::upper_bound(v.begin() + first, v.begin() + last, cell);
    auto j = static_cast<std::size_t>(it - v.begin());
    return std::clamp(j, first + 1, last - 1) - 1;
  };
  return wide_ ? search(wide32_) : search(narrow16_);
}

}  // namespace acdf
