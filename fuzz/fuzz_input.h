#pragma once
// Helpers shared by the fuzz targets: reading typed values off the fuzzer's bytes (zeros once
// they run out, so every input decodes), a scratch file for readers that only take a path, and
// the check that turns a broken invariant into a crash libFuzzer records.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace acdf::fuzz {

class Bytes {
 public:
  Bytes(const uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  bool empty() const { return pos_ >= size_; }
  std::size_t remaining() const { return empty() ? 0 : size_ - pos_; }

  template <class T>
  T take() {
    T value{};
    const std::size_t n = std::min(sizeof(T), remaining());
    if (n > 0) std::memcpy(&value, data_ + pos_, n);
    pos_ += sizeof(T);
    return value;
  }
  uint8_t byte() { return take<uint8_t>(); }

 private:
  const uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

// Aborts with the broken invariant: libFuzzer saves the input as a crash.
[[noreturn]] inline void fail(const char* what, const std::string& detail = {}) {
  std::fprintf(stderr, "fuzz invariant broken: %s %s\n", what, detail.c_str());
  std::abort();
}
inline void require(bool ok, const char* what, const std::string& detail = {}) {
  if (!ok) fail(what, detail);
}

// A file under /dev/shm (or TMPDIR) holding `size` bytes, removed by the destructor. The path ends
// in `suffix` (readers that pick a format by extension see it).
class ScratchFile {
 public:
  ScratchFile(const uint8_t* data, std::size_t size, const std::string& suffix) {
    const char* dir =
        access("/dev/shm", W_OK) == 0 ? "/dev/shm" : (std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp");
    path_ = std::string(dir) + "/acdf-fuzz-" + std::to_string(getpid()) + suffix;
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (!f || (size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) fail("cannot write", path_);
  }
  ~ScratchFile() { std::remove(path_.c_str()); }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace acdf::fuzz
