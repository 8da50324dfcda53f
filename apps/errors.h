#pragma once
// Error types of the acdf command-line program. main() turns each into exactly one line on
// stderr and an exit code (see main.cpp): a bad input file or a bad command line exits 2.

#include <stdexcept>
#include <string>

namespace acdf::app {

// A problem with an input file. what() is "<file>: <problem>", a single line.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& problem);
  const std::string& file() const { return file_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_;
  std::string problem_;
};

// A command line that parses but makes no sense (e.g. `--simplifier dp --max-points 64`).
class UsageError : public std::runtime_error {
 public:
  explicit UsageError(const std::string& message);
};

// Collapses line breaks and tabs into single spaces, replaces other control characters with '?'
// and trims, so a message fits on one line.
std::string oneLine(const std::string& text);

}  // namespace acdf::app
