#include "acdf/sampling/vertex_indices.h"

namespace acdf {

void VertexIndices::append(const VertexIndices& other) {
  if (width_ == other.width_) {
    narrow8_.insert(narrow8_.end(), other.narrow8_.begin(), other.narrow8_.end());
    narrow16_.insert(narrow16_.end(), other.narrow16_.begin(), other.narrow16_.end());
    wide32_.insert(wide32_.end(), other.wide32_.begin(), other.wide32_.end());
    return;
  }
  for (std::size_t i = 0; i < other.size(); ++i) push_back(other[i]);
}

}  // namespace acdf
