#pragma once
// Checks shared by every input reader: the path names a non-empty regular file we can read.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace acdf::app {

// Throws FileError ("no such file", "is a directory", "file is empty", ...) unless `path` is a
// readable, non-empty regular file (symlinks followed). Returns its size in bytes.
std::uintmax_t checkInputFile(const std::string& path);

// The whole file, after checkInputFile(). Throws FileError if it cannot be read.
std::vector<unsigned char> readFileBytes(const std::string& path);

}  // namespace acdf::app
