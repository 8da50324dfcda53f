// Fuzzes Cascade::deserialize, the reader of cached tables (table_cache.h): any bytes either throw
// SerializationError with a one-line "cascade: " message, or give a table that serializes back to
// the same bytes and, in every slice, samples inside its domain with a finite positive pdf that
// pdf() reproduces, and inverts into [0, 1].

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "acdf/sampling/byte_io.h"
#include "acdf/sampling/cascade.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace acdf;
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    const Cascade c = Cascade::deserialize(bytes);
    fuzz::require(c.serialize() == std::vector<std::byte>(bytes.begin(), bytes.end()), "cascade: round trip differs");
    const std::size_t k = c.conditioningDims(), n = c.sampledDims();
    std::vector<float> condition(k), u(n), x(n);
    for (std::size_t slice = 0; slice < std::min<std::size_t>(c.slices(), 64); ++slice) {
      // The centre of the slice's cell on each conditioning axis (row-major, axis 0 slowest).
      std::size_t rest = slice;
      for (std::size_t d = k; d-- > 0;) {
        const GridAxis& a = c.axes()[d];
        const auto cell = static_cast<uint32_t>(rest % a.cells());
        rest /= a.cells();
        condition[d] = a.place(cell, cell + 1, 0.5);
      }
      fuzz::require(c.sliceOf(condition) == slice, "cascade: condition maps to another slice");
      for (float v : {0.0f, 0.25f, 0.5f, 0.75f, kOneMinusEpsilon}) {
        std::fill(u.begin(), u.end(), v);
        const SampleND s = c.sample(condition, u);
        fuzz::require(s.pdf > 0.0f && std::isfinite(s.pdf), "cascade: sample pdf not finite and positive");
        for (std::size_t d = 0; d < n; ++d)
          fuzz::require(c.axes()[k + d].contains(s.x[d]), "cascade: sample outside the domain");
        fuzz::require(c.pdf(condition, s.point()) == s.pdf, "cascade: pdf() differs from the sample's pdf");
        c.invert(condition, s.point(), x);
        for (float w : x) fuzz::require(w >= 0.0f && w <= 1.0f, "cascade: inverted variate outside [0, 1]");
      }
    }
  } catch (const SerializationError& e) {
    const std::string message = e.what();
    fuzz::require(message.rfind("cascade: ", 0) == 0, "cascade: message does not start with 'cascade: '", message);
    fuzz::require(message.find('\n') == std::string::npos, "cascade: message spans lines", message);
  }
  return 0;
}
