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

// A file the program ships with (the neural BRDF fits, the plot script): <prefix>/share/acdf/<name>
// where an install put it there (the wheel does; <prefix>/bin holds the program, or
// <prefix>/lib/python3.X/site-packages/acdf.scripts in a wheel auditwheel repaired), else
// `sourceTreePath`, the copy in the source tree the build was configured from.
std::string bundledFile(const std::string& name, const std::string& sourceTreePath);

}  // namespace acdf::app
