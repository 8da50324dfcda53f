#pragma once
// Error types of the acdf command-line program. main() turns each into exactly one line on
// stderr and an exit code (see main.cpp): a bad input file (FileError) or a bad command line
// (UsageError) exits 2.

#include <stdexcept>
#include <string>
#include <string_view>

#include "acdf/sampling/file_error.h"
#include "acdf/sampling/option_error.h"

namespace acdf::app {

// A command line that parses but makes no sense (e.g. `--simplifier douglas-peucker --max-points 64`).
class UsageError : public std::runtime_error {
 public:
  explicit UsageError(const std::string& message);
};

// "--max-points" for option max_points: an option's flag, in kebab case.
std::string flagName(std::string_view option);

// "--max-points must be at least 2 (the end points)" for option max_points.
std::string flagError(const OptionError& e);

// `validate(options)` for options built from flags named as the options are, in kebab case
// (max_points is --max-points): a rejected option becomes a UsageError naming its flag, prefixed
// with `command` ("envmap-stats: ") when not empty.
template <class Options>
void validateFlags(const Options& options, const std::string& command = "") {
  try {
    validate(options);
  } catch (const OptionError& e) {
    throw UsageError(command + flagError(e));
  }
}

}  // namespace acdf::app
