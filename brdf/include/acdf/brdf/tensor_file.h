#pragma once
// The tensor file format of the RGL material database (Dupuy & Jakob 2018; Mitsuba's TensorFile),
// the container of `.bsdf` files: named, typed, n-dimensional arrays.
//
// Layout (little-endian):
//   "tensor_file\0"                 12 bytes
//   version                         2 bytes, major then minor (1, 0)
//   field count                     uint32
//   per field: name length (uint16), name bytes, ndim (uint16), dtype (uint8), data offset
//              from the start of the file (uint64), ndim extents (uint64 each, slowest first)
//   the fields' data, row-major, at their offsets (the writer aligns them to 8 bytes)
//
// dtype codes: 1 uint8, 2 int8, 3 uint16, 4 int16, 5 uint32, 6 int32, 7 uint64, 8 int64,
// 9 float16, 10 float32, 11 float64.
//
// parse() checks the container only — magic, version, the header inside the file, known dtypes,
// at most kMaxDims extents whose product fits, every field's data inside the file, no name twice —
// and throws FileError naming the file, the field and the problem. What the fields mean is the
// reader's business (rgl.h).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "acdf/sampling/file_error.h"

namespace acdf {

struct TensorField {
  enum class Type : uint8_t { UInt8 = 1, Int8, UInt16, Int16, UInt32, Int32, UInt64, Int64, Float16, Float32, Float64 };
  static constexpr std::size_t kMaxDims = 8;

  Type type = Type::UInt8;
  std::vector<uint64_t> shape;      // slowest first; empty = a scalar
  std::vector<unsigned char> data;  // elements() × elementBytes(type), little-endian

  uint64_t elements() const;
  static std::size_t elementBytes(Type type);
  static const char* typeName(Type type);  // "float32", ...

  static TensorField floats(std::vector<uint64_t> shape, std::span<const float> values);
  static TensorField bytes(std::vector<uint64_t> shape, std::span<const unsigned char> values);
};

class TensorFile {
 public:
  static constexpr std::size_t kMagicBytes = 12;
  // True when `head` starts with "tensor_file\0" (what a reader recognises the format by).
  static bool hasMagic(std::span<const unsigned char> head);

  // Throws FileError("<file>: <problem>") for anything parse() checks (see above).
  static TensorFile parse(std::span<const unsigned char> bytes, const std::string& file);
  // Also refuses a missing, unreadable or empty file.
  static TensorFile load(const std::filesystem::path& path);

  // Appends a field; throws std::invalid_argument for a name used twice, longer than 65535 bytes,
  // more than kMaxDims extents or data that does not match the shape.
  void add(std::string name, TensorField field);
  // The field, or null.
  const TensorField* find(const std::string& name) const;
  const std::vector<std::pair<std::string, TensorField>>& fields() const { return fields_; }

  std::vector<unsigned char> serialize() const;
  // Temporary file + rename: a failure leaves no partial file. Throws FileError.
  void save(const std::filesystem::path& path) const;

 private:
  std::vector<std::pair<std::string, TensorField>> fields_;
};

}  // namespace acdf
