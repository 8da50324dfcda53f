#pragma once
// Little-endian binary encoding for tables saved to disk (cascade_io.cpp, table_cache.h).
//
// ByteWriter appends fixed-width integers and IEEE floats (their exact bits, so a round trip is
// bit-identical) to a byte vector. ByteReader reads them back and checks every length against the
// bytes left before it allocates, so a corrupt count can neither read past the end nor ask for
// gigabytes: anything that does not fit throws SerializationError. Readers of a format validate
// the values themselves and throw the same type, with a message saying what was wrong.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace acdf {

// Serialized data that cannot be decoded: truncated, inconsistent or from another format.
// what() is one line saying what was wrong (the reader does not know the file's name; callers
// that do prefix it).
class SerializationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The value types the byte streams carry: integers and floating point, little-endian.
template <class T>
concept Arithmetic = std::is_arithmetic_v<T>;

namespace detail {
// The unsigned integer with T's size, to move T's bits byte by byte.
template <class T>
using BitsOf = std::conditional_t<
    sizeof(T) == 1, uint8_t,
    std::conditional_t<sizeof(T) == 2, uint16_t, std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;
}  // namespace detail

class ByteWriter {
 public:
  template <Arithmetic T>
  void put(T value) {
    using Bits = detail::BitsOf<T>;
    const auto bits = std::bit_cast<Bits>(value);
    for (std::size_t i = 0; i < sizeof(T); ++i) bytes_.push_back(static_cast<std::byte>(bits >> (8 * i)));
  }
  // A count (u64) followed by the values.
  template <class T>
  void putArray(std::span<const T> values) {
    put<uint64_t>(values.size());
    for (T v : values) put(v);
  }
  void putBytes(std::span<const std::byte> bytes) { bytes_.insert(bytes_.end(), bytes.begin(), bytes.end()); }

  const std::vector<std::byte>& bytes() const { return bytes_; }
  std::vector<std::byte> take() { return std::move(bytes_); }

 private:
  std::vector<std::byte> bytes_;
};

class ByteReader {
 public:
  // `what` names the data in error messages, e.g. "cascade".
  ByteReader(std::span<const std::byte> bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}

  template <Arithmetic T>
  T get() {
    need(sizeof(T), "a value");
    return decode<T>();
  }
  // Reads what putArray wrote; `name` is for the message if the count exceeds the bytes left.
  template <class T>
  std::vector<T> getArray(const char* name) {
    const uint64_t count = get<uint64_t>();
    if (count > remaining() / sizeof(T)) {
      fail(std::string("truncated (") + name + ": " + std::to_string(count) + " entries of " +
           std::to_string(sizeof(T)) + " bytes, " + std::to_string(remaining()) + " bytes left)");
    }
    std::vector<T> values(static_cast<std::size_t>(count));
    for (T& v : values) v = decode<T>();  // in bounds: checked above
    return values;
  }
  std::span<const std::byte> getBytes(std::size_t count) {
    need(count, "bytes");
    const std::span<const std::byte> out = bytes_.subspan(pos_, count);
    pos_ += count;
    return out;
  }

  std::size_t remaining() const { return bytes_.size() - pos_; }
  // Throws unless every byte was consumed (trailing garbage means the wrong length or format).
  void expectEnd() const {
    if (remaining() != 0) fail(std::to_string(remaining()) + " unexpected trailing bytes");
  }
  // Throws SerializationError("<what>: <problem>").
  [[noreturn]] void fail(const std::string& problem) const { throw SerializationError(what_ + ": " + problem); }

 private:
  template <class T>
  T decode() {
    using Bits = detail::BitsOf<T>;
    Bits bits = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i)
      bits |= static_cast<Bits>(std::to_integer<Bits>(bytes_[pos_ + i]) << (8 * i));
    pos_ += sizeof(T);
    return std::bit_cast<T>(bits);
  }
  void need(std::size_t count, const char* what) const {
    if (count > remaining())
      fail(std::string("truncated (") + what + " needs " + std::to_string(count) + " bytes, " +
           std::to_string(remaining()) + " left)");
  }

  std::span<const std::byte> bytes_;
  std::size_t pos_ = 0;
  std::string what_;
};

}  // namespace acdf
