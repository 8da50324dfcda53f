#include "acdf/sampling/file_error.h"

#include <utility>

namespace acdf {

std::string oneLine(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  bool pendingBreak = false;
  for (char c : text) {
    if (c == '\n' || c == '\r' || c == '\t') {
      pendingBreak = true;
      continue;
    }
    if (pendingBreak && !out.empty() && out.back() != ' ' && c != ' ') out.push_back(' ');
    pendingBreak = false;
    const auto u = static_cast<unsigned char>(c);
    out.push_back(u < 0x20 || u == 0x7f ? '?' : c);  // no other control characters either
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

FileError::FileError(std::string file, std::string problem)
    : std::runtime_error(oneLine(file) + ": " + oneLine(problem)),
      file_(std::move(file)),
      problem_(std::move(problem)) {}

}  // namespace acdf
