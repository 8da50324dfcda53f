#include "files.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <system_error>

#include <fmt/format.h>

#include "acdf/sampling/regular_file.h"
#include "acdf/sampling/temporary_files.h"
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

void writeTextFileAtomically(const std::string& path, std::string_view text) {
  std::random_device random;
  const std::string temp = fmt::format("{}.tmp-{:08x}", path, static_cast<unsigned>(random()));
  const TemporaryFileGuard guard(temp);  // removed if a signal kills us mid-write
  std::error_code ec;
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (out) out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) {
      fs::remove(temp, ec);
      throw FileError(path, "cannot write the temporary file " + temp);
    }
  }
  fs::rename(temp, path, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw FileError(path, "cannot rename the temporary file into place");
  }
}

}  // namespace acdf::app
