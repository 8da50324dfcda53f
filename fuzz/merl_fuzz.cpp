// Fuzzes the MERL .binary reader (acdf/brdf/merl.h). The input's first byte picks the file's
// length: the rest of the input as it is (header checks, truncation), or padded with zeros —
// sparsely, by truncate() — to the exact MERL size or a few bytes off it, so the dimension check, the size
// checks and the value conversion (NaN, Inf, beyond-float, negatives in the input's first
// doubles) are all reached. Invariants: load() returns a table or throws FileError with a
// one-line message naming the file; a loaded table evaluates to finite, non-negative values.

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "acdf/brdf/merl.h"
#include "fuzz_input.h"

namespace {

constexpr std::size_t kFileBytes = 12 + 3 * acdf::MerlBrdf::kCells * sizeof(double);

void checkEval(const acdf::MerlBrdf& brdf, acdf::fuzz::Bytes& angles) {
  for (int i = 0; i < 8 && !angles.empty(); ++i) {
    const double th = angles.take<double>(), td = angles.take<double>(), pd = angles.take<double>();
    if (!std::isfinite(th) || !std::isfinite(td) || !std::isfinite(pd)) continue;
    for (auto mode : {acdf::MerlBrdf::Interpolation::Nearest, acdf::MerlBrdf::Interpolation::Trilinear}) {
      const acdf::Rgb v = brdf.withInterpolation(mode).evalHalfDiff(std::fabs(th), std::fabs(td), pd);
      for (float c : {v.r, v.g, v.b})
        acdf::fuzz::require(std::isfinite(c) && c >= 0.0f, "merl: eval not finite and >= 0");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace acdf;
  if (size == 0) return 0;
  const uint8_t mode = data[0];
  const fuzz::ScratchFile file(data + 1, size - 1, ".binary");
  // One input in 16 is padded (a 35 MB read is slow), to the exact size when the high nibble is
  // 0, else to that nibble - 8 bytes off it.
  if ((mode & 15) == 1) {
    const int offset = (mode >> 4) == 0 ? 0 : (mode >> 4) - 8;
    const auto length = static_cast<off_t>(kFileBytes) + offset;
    if (truncate(file.path().c_str(), length) != 0) fuzz::fail("cannot resize", file.path());
  }
  try {
    const MerlBrdf brdf = MerlBrdf::load(file.path());
    fuzz::Bytes angles(data + 1, size - 1);
    checkEval(brdf, angles);
  } catch (const FileError& e) {
    const std::string message = e.what();
    fuzz::require(message.rfind(file.path() + ": ", 0) == 0, "merl: message does not name the file", message);
    fuzz::require(message.find('\n') == std::string::npos, "merl: message spans lines", message);
  }
  return 0;
}
