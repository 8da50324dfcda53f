#pragma once
// Internal: the checks every brdf/ reader makes before opening a file, so each error names the
// file and says what is wrong with it.

#include <filesystem>
#include <string>
#include <system_error>

#include "acdf/brdf/merl.h"  // BrdfFileError

namespace acdf::detail {

// Throws BrdfFileError unless `path` is an existing regular file (not a directory, FIFO, ...).
inline void requireRegularFile(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  const std::string name = path.string();
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) throw BrdfFileError(name, "no such file");
  if (ec) throw BrdfFileError(name, "cannot access file (" + ec.message() + ")");
  if (status.type() == fs::file_type::directory) throw BrdfFileError(name, "is a directory, not a file");
  if (status.type() != fs::file_type::regular) throw BrdfFileError(name, "not a regular file");
}

}  // namespace acdf::detail
