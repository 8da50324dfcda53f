#include "write_atomically.h"

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

namespace {

std::string errnoText() { return std::strerror(errno); }

}  // namespace

void writeFileAtomically(const std::string& name, const unsigned char* data, std::size_t size) {
  // The temporary sits next to the target so the rename stays within one file system (and is
  // atomic). O_EXCL: never write into somebody else's file; mode 0666 lets the umask decide,
  // as for any newly created file.
  // The guard (removal if a signal kills us mid-write) is taken before the file exists, so no
  // signal finds it unguarded; it is dropped again for a name that turns out to be taken.
  std::random_device random;
  std::string temp;
  std::unique_ptr<TemporaryFileGuard> guard;
  int fd = -1;
  for (int attempt = 0; attempt < 16 && fd < 0; ++attempt) {
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, ".tmp-%08x", static_cast<unsigned>(random()));
    temp = name + suffix;
    guard = std::make_unique<TemporaryFileGuard>(temp);
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) break;
    const int openError = errno;
    guard.reset();
    errno = openError;  // for the message below
    if (openError != EEXIST) break;
  }
  if (fd < 0) throw FileError(name, "cannot create a temporary file next to it (" + errnoText() + ")");

  const auto fail = [&](const std::string& problem) {
    const std::string reason = problem + " (" + errnoText() + ")";
    if (fd >= 0) ::close(fd);
    ::unlink(temp.c_str());
    throw FileError(name, reason);
  };
  std::size_t written = 0;
  while (written < size) {
    const ssize_t n = ::write(fd, data + written, size - written);
    if (n < 0 && errno == EINTR) continue;
    if (n == 0) errno = EIO;  // write() made no progress without saying why
    if (n <= 0) fail("cannot write the temporary file " + temp);
    written += static_cast<std::size_t>(n);
  }
  const int closed = ::close(fd);
  fd = -1;
  if (closed != 0) fail("cannot write the temporary file " + temp);
  if (std::rename(temp.c_str(), name.c_str()) != 0) fail("cannot rename the temporary file into place");
}

}  // namespace acdf
