#pragma once
// Error types of the acdf command-line program. main() turns each into exactly one line on
// stderr and an exit code (see main.cpp): a bad input file (FileError) or a bad command line
// (UsageError) exits 2.

#include <stdexcept>
#include <string>

#include "acdf/sampling/file_error.h"

namespace acdf::app {

// A command line that parses but makes no sense (e.g. `--simplifier douglas-peucker --max-points 64`).
class UsageError : public std::runtime_error {
 public:
  explicit UsageError(const std::string& message);
};

}  // namespace acdf::app
