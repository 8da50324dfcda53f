#pragma once
// Reader for NumPy .npy arrays (format versions 1.0, 2.0 and 3.0).
//
// Accepted: little-endian float32 ('<f4') or float64 ('<f8'), 1 to 4 dimensions, every dimension
// > 0, C (row-major) order. float64 is converted to float; a finite value beyond the float range
// is an error. The values themselves are not checked (negative, NaN and Inf are the caller's
// business: acdf::checkNonNegativeFinite reports them by index).
// Every problem is reported as FileError("<name>: <problem>").

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace acdf::app {

enum class NpyDtype { Float32, Float64 };

struct NpyArray {
  std::vector<std::size_t> shape;      // 1..4 entries, each > 0
  NpyDtype dtype = NpyDtype::Float32;  // as stored in the file
  int majorVersion = 1;
  std::vector<float> values;  // C order, product(shape) entries
};

inline constexpr std::size_t kNpyMaxDims = 4;

// `name` is used only in error messages.
NpyArray parseNpy(std::span<const unsigned char> bytes, const std::string& name);

// Reads and parses a file (missing, directory and empty files are errors too).
NpyArray readNpy(const std::string& path);

// True if the bytes start with the .npy magic string "\x93NUMPY".
bool hasNpyMagic(std::span<const unsigned char> bytes);

}  // namespace acdf::app
