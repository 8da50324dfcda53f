#pragma once
// Grid-vertex indices of CDF breakpoints, stored in the narrowest of 8, 16 or 32 bits that holds
// every index of the grid (at most 255, 65535 cells, or more). A BRDF table's azimuth axis has
// 32 cells: a byte per breakpoint instead of two is a sixth less storage for that level.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace acdf {

class VertexIndices {
 public:
  VertexIndices() = default;
  // largestVertex: the largest index that will ever be stored (the grid's cell count).
  explicit VertexIndices(uint32_t largestVertex)
      : width_(largestVertex <= 0xFFu     ? 1
               : largestVertex <= 0xFFFFu ? 2
                                          : 4) {}

  // Bytes per stored index: 1, 2 or 4.
  unsigned width() const { return width_; }
  std::size_t size() const { return width_ == 1 ? narrow8_.size() : width_ == 2 ? narrow16_.size() : wide32_.size(); }
  std::size_t bytes() const { return size() * width_; }

  // Forced inline, as BreakpointCdf's accessors are (breakpoint_cdf.h says why).
  [[gnu::always_inline]] uint32_t operator[](std::size_t i) const {
    return width_ == 1 ? narrow8_[i] : width_ == 2 ? narrow16_[i] : wide32_[i];
  }

  void push_back(uint32_t vertex) {
    if (width_ == 1)
      narrow8_.push_back(static_cast<uint8_t>(vertex));
    else if (width_ == 2)
      narrow16_.push_back(static_cast<uint16_t>(vertex));
    else
      wide32_.push_back(vertex);
  }
  void append(const VertexIndices& other);
  void reserve(std::size_t n) {
    if (width_ == 1)
      narrow8_.reserve(n);
    else if (width_ == 2)
      narrow16_.reserve(n);
    else
      wide32_.reserve(n);
  }
  void shrink_to_fit() {
    narrow8_.shrink_to_fit();
    narrow16_.shrink_to_fit();
    wide32_.shrink_to_fit();
  }

  // How many of the sorted indices [first, last) are <= cell. Inline (forced, as operator[]) and
  // branchless within the search (the width test is the same on every call of a table): it sits
  // on every pdf() call.
  [[gnu::always_inline]] std::size_t countAtMost(std::size_t first, std::size_t last, uint32_t cell) const {
    if (width_ == 1) return countAtMost(narrow8_.data() + first, last - first, cell);
    if (width_ == 2) return countAtMost(narrow16_.data() + first, last - first, cell);
    return countAtMost(wide32_.data() + first, last - first, cell);
  }

 private:
  // Every index before `base` is <= cell and the answer lies in [base, base + length]; halving
  // keeps that, and the loop has no data-dependent branch (the compiler emits a conditional move).
  template <class T>
  static std::size_t countAtMost(const T* v, std::size_t n, uint32_t cell) {
    if (n == 0) return 0;
    const T* base = v;
    std::size_t length = n;
    while (length > 1) {
      const std::size_t half = length / 2;
      base = base[half] <= cell ? base + half : base;
      length -= half;
    }
    return static_cast<std::size_t>(base - v) + (*base <= cell ? 1 : 0);
  }

  unsigned width_ = 2;
  std::vector<uint8_t> narrow8_;
  std::vector<uint16_t> narrow16_;
  std::vector<uint32_t> wide32_;
};

}  // namespace acdf
