#pragma once
// The one error type for a problem with a file, whichever library meets it: a BRDF, an image, a
// scene, a table or an array the command line reads or writes. The acdf command-line tool prints
// what() as it is and exits 2.

#include <stdexcept>
#include <string>

namespace acdf {

// A problem with a file (missing, malformed, unwritable). what() is "<file>: <problem>", one line
// (see oneLine); file() and problem() are kept as given.
class FileError : public std::runtime_error {
 public:
  FileError(std::string file, std::string problem);
  const std::string& file() const { return file_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_;
  std::string problem_;
};

// Collapses line breaks and tabs into single spaces, replaces other control characters with '?'
// and trims, so a message fits on one line.
std::string oneLine(const std::string& text);

}  // namespace acdf
