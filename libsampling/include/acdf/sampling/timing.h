#pragma once
// Wall-clock time for the set-up and build figures the library and the tools report.

#include <chrono>

namespace acdf {

// Milliseconds on the steady clock since `start`.
inline double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace acdf
