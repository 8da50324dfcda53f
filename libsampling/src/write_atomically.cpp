#include "acdf/sampling/write_atomically.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>

#include "acdf/sampling/file_error.h"
#include "acdf/sampling/temporary_files.h"

namespace acdf {

void writeFileAtomically(const std::string& path, const std::function<void(const std::string& temporary)>& write) {
  // O_EXCL: never write into somebody else's file; mode 0666 lets the umask decide, as for any
  // newly created file. The guard is taken before the file exists, so no signal finds it
  // unguarded; it is dropped again for a name that turns out to be taken.
  std::random_device random;
  std::string temp;
  std::unique_ptr<TemporaryFileGuard> guard;
  int fd = -1;
  for (int attempt = 0; attempt < 16 && fd < 0; ++attempt) {
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, ".tmp-%08x", static_cast<unsigned>(random()));
    temp = path + suffix;
    guard = std::make_unique<TemporaryFileGuard>(temp);
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) break;
    const int openError = errno;
    guard.reset();
    errno = openError;  // for the message below
    if (openError != EEXIST) break;
  }
  if (fd < 0)
    throw FileError(path, std::string("cannot create a temporary file next to it (") + std::strerror(errno) + ")");
  ::close(fd);
  try {
    write(temp);
  } catch (...) {
    ::unlink(temp.c_str());
    throw;
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(temp.c_str());
    throw FileError(path, "cannot rename the temporary file into place (" + reason + ")");
  }
}

void writeFileAtomically(const std::string& path, std::span<const std::byte> bytes) {
  writeFileAtomically(path, [&](const std::string& temp) {
    const auto fail = [&](int fd) {
      const std::string reason = std::strerror(errno);
      if (fd >= 0) ::close(fd);
      throw FileError(path, "cannot write the temporary file " + temp + " (" + reason + ")");
    };
    const int fd = ::open(temp.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd < 0) fail(fd);
    for (std::size_t written = 0; written < bytes.size();) {
      const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
      if (n < 0 && errno == EINTR) continue;
      if (n == 0) errno = EIO;  // write() made no progress without saying why
      if (n <= 0) fail(fd);
      written += static_cast<std::size_t>(n);
    }
    if (::close(fd) != 0) fail(-1);
  });
}

void writeFileAtomically(const std::string& path, std::string_view text) {
  writeFileAtomically(path, std::as_bytes(std::span(text.data(), text.size())));
}

}  // namespace acdf
