// Fuzzes the .npy reader of the acdf CLI (apps/npy.h): any bytes either parse into an array that
// matches its header or raise FileError with a one-line message naming the file.

#include <cmath>
#include <cstdint>
#include <limits>

#include "errors.h"
#include "fuzz_input.h"
#include "npy.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace acdf;
  try {
    const app::NpyArray array = app::parseNpy({data, size}, "input.npy");
    fuzz::require(!array.shape.empty() && array.shape.size() <= app::kNpyMaxDims, "npy: shape rank");
    std::size_t count = 1;
    for (std::size_t n : array.shape) {
      fuzz::require(n > 0, "npy: zero dimension accepted");
      count *= n;
    }
    fuzz::require(count == array.values.size(), "npy: value count differs from the shape");
    const std::size_t item = array.dtype == app::NpyDtype::Float32 ? 4 : 8;
    fuzz::require(count * item < size, "npy: more data than bytes");
  } catch (const FileError& e) {
    const std::string message = e.what();
    fuzz::require(message.rfind("input.npy: ", 0) == 0, "npy: message does not name the file", message);
    fuzz::require(message.find('\n') == std::string::npos, "npy: message spans lines", message);
  }
  return 0;
}
