#pragma once
// Grid-vertex indices of CDF breakpoints, stored as 16-bit integers when every index fits
// (grids of at most 65535 cells) and as 32-bit otherwise.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace acdf {

class VertexIndices {
 public:
  VertexIndices() = default;
  // largestVertex: the largest index that will ever be stored (the grid's cell count).
  explicit VertexIndices(uint32_t largestVertex) : wide_(largestVertex > 0xFFFFu) {}

  bool wide() const { return wide_; }
  std::size_t size() const { return wide_ ? wide32_.size() : narrow16_.size(); }
  std::size_t bytes() const {
    return narrow16_.size() * sizeof(uint16_t) + wide32_.size() * sizeof(uint32_t);
  }

  uint32_t operator[](std::size_t i) const { return wide_ ? wide32_[i] : narrow16_[i]; }

  void push_back(uint32_t vertex) {
    if (wide_) wide32_.push_back(vertex);
    else narrow16_.push_back(static_cast<uint16_t>(vertex));
  }
  void append(const VertexIndices& other);
  void reserve(std::size_t n) { wide_ ? wide32_.reserve(n) : narrow16_.reserve(n); }
  void shrink_to_fit() { narrow16_.shrink_to_fit(); wide32_.shrink_to_fit(); }

  // Index j in [first, last-1) of the breakpoint interval [v[j], v[j+1]) that holds `cell`,
  // given v[first] <= cell < v[last-1]. Inline and branchless: it sits on every pdf() call.
  std::size_t intervalOf(std::size_t first, std::size_t last, uint32_t cell) const {
    return wide_ ? lastAtMost(wide32_.data(), first, last, cell) : lastAtMost(narrow16_.data(), first, last, cell);
  }

 private:
  // Largest j in [first, last-2] with v[j] <= cell: a binary search whose loop has no
  // data-dependent branch (the compiler emits a conditional move).
  template <class T>
  static std::size_t lastAtMost(const T* v, std::size_t first, std::size_t last, uint32_t cell) {
    std::size_t base = first, length = last - 1 - first;  // candidates [base, base + length)
    while (length > 1) {
      const std::size_t half = length / 2;
      base = v[base + half] <= cell ? base + half : base;
      length -= half;
    }
    return base;
  }

  bool wide_ = false;
  std::vector<uint16_t> narrow16_;
  std::vector<uint32_t> wide32_;
};

}  // namespace acdf
