#pragma once
// Option helpers shared by the subcommands.

#include <chrono>

#include <CLI/CLI.hpp>

namespace acdf::app {

// Accepts a non-negative integer, also written like 1e6; rewrites it to plain digits for CLI11's
// conversion (which would otherwise wrap "-5" around to 2^64 - 5).
CLI::Validator nonNegativeInteger();

using Clock = std::chrono::steady_clock;

inline double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace acdf::app
