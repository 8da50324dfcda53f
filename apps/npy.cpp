#include "npy.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string_view>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "errors.h"
#include "files.h"

namespace acdf::app {

static_assert(std::endian::native == std::endian::little, "the .npy reader copies '<f4' / '<f8' data as is");

namespace {

constexpr unsigned char kMagic[6] = {0x93, 'N', 'U', 'M', 'P', 'Y'};

// Text taken from the file, made safe to print: non-ASCII and control bytes as \xNN.
std::string printable(std::string_view text) {
  std::string out;
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x7f)
      out += fmt::format("\\x{:02x}", u);
    else
      out.push_back(c);
  }
  return out;
}

std::string shapeString(const std::vector<std::size_t>& shape) {
  if (shape.size() == 1) return fmt::format("({},)", shape[0]);
  return fmt::format("({})", fmt::join(shape, ", "));
}

// A parsed Python literal of the few kinds a .npy header dict holds.
struct Value {
  enum class Kind { String, Bool, Tuple, Other } kind = Kind::Other;
  std::string text;                  // String
  bool flag = false;                 // Bool
  std::vector<std::size_t> numbers;  // Tuple of non-negative integers
};

// Parser for the header: a Python dict literal such as
//   {'descr': '<f4', 'fortran_order': False, 'shape': (3, 4), }
// followed by padding spaces and a newline.
class HeaderParser {
 public:
  HeaderParser(std::string_view text, const std::string& name) : text_(text), name_(name) {}

  // key -> value; throws on syntax errors or duplicate keys.
  std::vector<std::pair<std::string, Value>> parseDict() {
    std::vector<std::pair<std::string, Value>> entries;
    skipSpace();
    expect('{', "'{' opening the header dict");
    skipSpace();
    while (!atEnd() && peek() != '}') {
      if (peek() != '\'' && peek() != '"') fail("expected a quoted key");
      std::string key = parseString();
      for (const auto& e : entries)
        if (e.first == key) fail(fmt::format("duplicate key '{}'", printable(key)));
      skipSpace();
      expect(':', fmt::format("':' after key '{}'", printable(key)));
      skipSpace();
      Value value = parseValue(key);
      entries.emplace_back(std::move(key), std::move(value));
      skipSpace();
      if (!atEnd() && peek() == ',') {
        ++pos_;
        skipSpace();
      } else if (atEnd() || peek() != '}') {
        fail("expected ',' or '}' after a value");
      }
    }
    expect('}', "'}' closing the header dict");
    for (; pos_ < text_.size(); ++pos_) {
      char c = text_[pos_];
      if (c != ' ' && c != '\n' && c != '\r' && c != '\t' && c != '\0') fail("unexpected text after the header dict");
    }
    return entries;
  }

 private:
  bool atEnd() const { return pos_ >= text_.size(); }
  char peek() const { return text_[pos_]; }

  [[noreturn]] void fail(const std::string& what) const {
    throw FileError(name_, fmt::format("bad .npy header: {} at header offset {}", what, pos_));
  }

  void expect(char c, const std::string& what) {
    if (atEnd() || peek() != c) fail("expected " + what);
    ++pos_;
  }

  void skipSpace() {
    while (!atEnd() && (peek() == ' ' || peek() == '\t' || peek() == '\n' || peek() == '\r')) ++pos_;
  }

  std::string parseString() {
    const char quote = peek();
    ++pos_;
    std::string out;
    while (!atEnd() && peek() != quote) {
      if (peek() == '\\') fail("escape sequences in strings are not supported");
      if (peek() == '\n') fail("unterminated string");
      out.push_back(peek());
      ++pos_;
    }
    if (atEnd()) fail("unterminated string");
    ++pos_;
    return out;
  }

  std::size_t parseInteger() {
    if (atEnd() || peek() < '0' || peek() > '9') fail("expected a non-negative integer in the shape");
    std::size_t value = 0;
    while (!atEnd() && peek() >= '0' && peek() <= '9') {
      const auto digit = static_cast<std::size_t>(peek() - '0');
      if (value > (std::numeric_limits<std::size_t>::max() - digit) / 10) fail("shape entry too large");
      value = value * 10 + digit;
      ++pos_;
    }
    if (!atEnd() && (peek() == 'L' || peek() == 'l')) ++pos_;  // Python 2 longs: (3L, 4L)
    return value;
  }

  Value parseValue(const std::string& key) {
    Value v;
    if (atEnd()) fail(fmt::format("missing value for '{}'", printable(key)));
    const char c = peek();
    if (c == '\'' || c == '"') {
      v.kind = Value::Kind::String;
      v.text = parseString();
    } else if (text_.substr(pos_, 4) == "True") {
      v.kind = Value::Kind::Bool;
      v.flag = true;
      pos_ += 4;
    } else if (text_.substr(pos_, 5) == "False") {
      v.kind = Value::Kind::Bool;
      v.flag = false;
      pos_ += 5;
    } else if (c == '(') {
      v.kind = Value::Kind::Tuple;
      ++pos_;
      skipSpace();
      while (!atEnd() && peek() != ')') {
        v.numbers.push_back(parseInteger());
        skipSpace();
        if (!atEnd() && peek() == ',') {
          ++pos_;
          skipSpace();
        } else if (atEnd() || peek() != ')') {
          fail("expected ',' or ')' in the shape tuple");
        }
      }
      expect(')', "')' closing the shape tuple");
    } else if (c == '[') {
      // A structured dtype's descr is a list of fields; skip it (brackets may nest).
      v.kind = Value::Kind::Other;
      int depth = 0;
      for (; !atEnd(); ++pos_) {
        if (peek() == '\'' || peek() == '"') {
          parseString();
          --pos_;
          continue;
        }
        if (peek() == '[' || peek() == '(') ++depth;
        if (peek() == ']' || peek() == ')') --depth;
        if (depth == 0) break;
      }
      expect(']', "']' closing a list");
    } else {
      fail(fmt::format("unsupported value for '{}'", printable(key)));
    }
    return v;
  }

  std::string_view text_;
  const std::string& name_;
  std::size_t pos_ = 0;
};

uint32_t readLe16(const unsigned char* p) { return uint32_t(p[0]) | (uint32_t(p[1]) << 8); }
uint32_t readLe32(const unsigned char* p) {
  return uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16) | (uint32_t(p[3]) << 24);
}

std::string elementName(std::size_t flat, const std::vector<std::size_t>& shape) {
  if (shape.size() == 1) return fmt::format("index {}", flat);
  std::vector<std::size_t> index(shape.size());
  std::size_t rest = flat;
  for (std::size_t d = shape.size(); d-- > 0;) {
    index[d] = rest % shape[d];
    rest /= shape[d];
  }
  return fmt::format("index {} (element [{}])", flat, fmt::join(index, ", "));
}

}  // namespace

bool hasNpyMagic(std::span<const unsigned char> bytes) {
  return bytes.size() >= sizeof(kMagic) && std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) == 0;
}

NpyArray parseNpy(std::span<const unsigned char> bytes, const std::string& name) {
  if (bytes.empty()) throw FileError(name, "file is empty");
  if (!hasNpyMagic(bytes)) {
    if (bytes.size() < sizeof(kMagic) && std::memcmp(bytes.data(), kMagic, bytes.size()) == 0)
      throw FileError(name, "truncated .npy file (ends inside the magic string)");
    throw FileError(name, "not a .npy file (missing the \\x93NUMPY magic string)");
  }
  if (bytes.size() < 8) throw FileError(name, "truncated .npy file (ends before the format version)");

  NpyArray array;
  const int major = bytes[6];
  const int minor = bytes[7];
  if (major < 1 || major > 3 || minor != 0)
    throw FileError(name,
                    fmt::format("unsupported .npy format version {}.{} (supported: 1.0, 2.0, 3.0)", major, minor));
  array.majorVersion = major;

  const std::size_t lengthBytes = major == 1 ? 2 : 4;
  if (bytes.size() < 8 + lengthBytes) throw FileError(name, "truncated .npy file (ends inside the header length)");
  const std::size_t headerLength = major == 1 ? readLe16(&bytes[8]) : readLe32(&bytes[8]);
  const std::size_t headerStart = 8 + lengthBytes;
  if (headerLength > bytes.size() - headerStart)
    throw FileError(name, fmt::format("truncated .npy file (header of {} bytes, but only {} bytes follow)",
                                      headerLength, bytes.size() - headerStart));
  const std::string_view header(reinterpret_cast<const char*>(&bytes[headerStart]), headerLength);

  HeaderParser parser(header, name);
  const auto entries = parser.parseDict();
  const Value* descr = nullptr;
  const Value* fortran = nullptr;
  const Value* shape = nullptr;
  for (const auto& [key, value] : entries) {
    if (key == "descr")
      descr = &value;
    else if (key == "fortran_order")
      fortran = &value;
    else if (key == "shape")
      shape = &value;
    else
      throw FileError(name, fmt::format("bad .npy header: unexpected key '{}'", printable(key)));
  }
  if (!descr) throw FileError(name, "bad .npy header: no 'descr' key");
  if (!fortran) throw FileError(name, "bad .npy header: no 'fortran_order' key");
  if (!shape) throw FileError(name, "bad .npy header: no 'shape' key");

  // dtype
  constexpr const char* kNeed = "need float32 ('<f4') or float64 ('<f8')";
  if (descr->kind != Value::Kind::String)
    throw FileError(name, fmt::format("unsupported dtype (structured or non-string 'descr'); {}", kNeed));
  const std::string d = printable(descr->text);
  if (d == "<f4")
    array.dtype = NpyDtype::Float32;
  else if (d == "<f8")
    array.dtype = NpyDtype::Float64;
  else if (d == ">f4" || d == ">f8")
    throw FileError(name, fmt::format("big-endian dtype '{}' is not supported; {} (convert with "
                                      "a.astype('<{}'))",
                                      d, kNeed, d.substr(1)));
  else
    throw FileError(name, fmt::format("unsupported dtype '{}'; {}", d, kNeed));

  if (fortran->kind != Value::Kind::Bool)
    throw FileError(name, "bad .npy header: 'fortran_order' is not True or False");
  if (fortran->flag)
    throw FileError(name,
                    "fortran_order is True (column-major data) and is not supported; save a "
                    "C-order array (np.ascontiguousarray)");

  if (shape->kind != Value::Kind::Tuple) throw FileError(name, "bad .npy header: 'shape' is not a tuple of integers");
  array.shape = shape->numbers;
  if (array.shape.empty()) throw FileError(name, "0-dimensional (scalar) array; need 1 to 4 dimensions");
  if (array.shape.size() > kNpyMaxDims)
    throw FileError(name, fmt::format("{} dimensions, shape {}; at most {} are supported", array.shape.size(),
                                      shapeString(array.shape), kNpyMaxDims));
  std::size_t count = 1;
  for (std::size_t i = 0; i < array.shape.size(); ++i) {
    if (array.shape[i] == 0)
      throw FileError(name, fmt::format("dimension {} has size 0, shape {}; empty arrays are not supported", i,
                                        shapeString(array.shape)));
    if (count > std::numeric_limits<std::size_t>::max() / array.shape[i])
      throw FileError(name, fmt::format("shape {} is too large", shapeString(array.shape)));
    count *= array.shape[i];
  }

  // data
  const std::size_t itemSize = array.dtype == NpyDtype::Float32 ? 4 : 8;
  const std::size_t dataStart = headerStart + headerLength;
  const std::size_t available = bytes.size() - dataStart;
  if (count > std::numeric_limits<std::size_t>::max() / itemSize)
    throw FileError(name, fmt::format("shape {} is too large", shapeString(array.shape)));
  const std::size_t needed = count * itemSize;
  if (available < needed)
    throw FileError(name, fmt::format("truncated data: shape {} of '{}' needs {} bytes, the file has {}",
                                      shapeString(array.shape), d, needed, available));
  if (available > needed)
    throw FileError(name, fmt::format("{} unexpected bytes after the data (shape {} of '{}' is {} bytes)",
                                      available - needed, shapeString(array.shape), d, needed));

  array.values.resize(count);
  const unsigned char* data = bytes.data() + dataStart;
  if (array.dtype == NpyDtype::Float32) {
    std::memcpy(array.values.data(), data, needed);
  } else {
    constexpr double kFloatMax = std::numeric_limits<float>::max();
    for (std::size_t i = 0; i < count; ++i) {
      double v;
      std::memcpy(&v, data + i * 8, 8);
      if (std::isfinite(v) && std::fabs(v) > kFloatMax)
        throw FileError(name, fmt::format("value at {} is {:g}, which overflows float32 (largest {:g})",
                                          elementName(i, array.shape), v, kFloatMax));
      array.values[i] = static_cast<float>(v);  // NaN and Inf stay NaN and Inf
    }
  }
  return array;
}

NpyArray readNpy(const std::string& path) {
  const std::vector<unsigned char> bytes = readFileBytes(path);
  return parseNpy(bytes, path);
}

}  // namespace acdf::app
