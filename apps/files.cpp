#include "files.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "acdf/sampling/regular_file.h"
#include "errors.h"

namespace acdf::app {

namespace fs = std::filesystem;

std::uintmax_t checkInputFile(const std::string& path) {
  if (path.empty()) throw FileError(path, "empty file name");
  if (const auto problem = regularFileProblem(path)) throw FileError(path, *problem);
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw FileError(path, "cannot read file size (" + ec.message() + ")");
  if (size == 0) throw FileError(path, "file is empty");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw FileError(path, std::string("cannot open file (") + std::strerror(errno) + ")");
  return size;
}

std::vector<unsigned char> readFileBytes(const std::string& path) {
  const std::uintmax_t size = checkInputFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, std::string("cannot open file (") + std::strerror(errno) + ")");
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (static_cast<std::uintmax_t>(in.gcount()) != size)
    throw FileError(path, "read error (file changed while reading?)");
  return bytes;
}

std::string bundledFile(const std::string& name, const std::string& sourceTreePath) {
  std::error_code ec;
  const fs::path program = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return sourceTreePath;
  // <prefix>/bin/acdf, or <prefix>/lib/python3.X/site-packages/acdf.scripts/acdf where auditwheel
  // moves the program of a repaired wheel (<prefix>/bin/acdf is then a script that runs it).
  const fs::path prefixes[] = {program.parent_path().parent_path(),
                               program.parent_path().parent_path().parent_path().parent_path().parent_path()};
  for (const fs::path& prefix : prefixes) {
    const fs::path installed = prefix / "share" / "acdf" / name;
    if (fs::is_regular_file(installed, ec)) return installed.string();
  }
  return sourceTreePath;
}

}  // namespace acdf::app
