#pragma once
// Option helpers shared by the subcommands.

#include <chrono>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "acdf/sampling/timing.h"
#include "errors.h"

namespace acdf::app {

// Accepts a non-negative integer, also written like 1e6; rewrites it to plain digits for CLI11's
// conversion (which would otherwise wrap "-5" around to 2^64 - 5).
CLI::Validator nonNegativeInteger();

// parse(value), with std::invalid_argument turned into "<command>: <option>: <problem>".
template <class Parse>
auto parseOption(const std::string& command, const std::string& option, const std::string& value, Parse parse) {
  try {
    return parse(value);
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("{}: {}: {}", command, option, e.what()));
  }
}

using Clock = std::chrono::steady_clock;  // the clock of millisecondsSince (acdf/sampling/timing.h)

}  // namespace acdf::app
