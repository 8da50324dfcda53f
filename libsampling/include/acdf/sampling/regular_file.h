#pragma once
// The check every reader makes before opening an input file, so the same problem reads the same
// whichever reader meets it. Callers throw it in their own error type, which names the file.

#include <filesystem>
#include <optional>
#include <string>
#include <system_error>

namespace acdf {

// Why `path` cannot be read as an input file ("no such file", "is a directory, not a file", ...),
// or nothing when it is an existing regular file.
inline std::optional<std::string> regularFileProblem(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) return "no such file";
  if (ec) return "cannot access file (" + ec.message() + ")";
  if (status.type() == fs::file_type::directory) return "is a directory, not a file";
  if (status.type() != fs::file_type::regular) return "not a regular file";
  return std::nullopt;
}

}  // namespace acdf
