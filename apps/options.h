#pragma once
// Option helpers shared by the subcommands.

#include <chrono>

#include <CLI/CLI.hpp>

#include "acdf/sampling/timing.h"

namespace acdf::app {

// Accepts a non-negative integer, also written like 1e6; rewrites it to plain digits for CLI11's
// conversion (which would otherwise wrap "-5" around to 2^64 - 5).
CLI::Validator nonNegativeInteger();

using Clock = std::chrono::steady_clock;  // the clock of millisecondsSince (acdf/sampling/timing.h)

}  // namespace acdf::app
