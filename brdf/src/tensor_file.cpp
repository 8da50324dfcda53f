#include "acdf/brdf/tensor_file.h"

#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "acdf/sampling/file_error.h"
#include "acdf/sampling/regular_file.h"
#include "acdf/sampling/write_atomically.h"

namespace acdf {

static_assert(std::endian::native == std::endian::little, "the tensor file reader copies little-endian data as is");

namespace {

constexpr unsigned char kMagic[TensorFile::kMagicBytes] = {'t', 'e', 'n', 's', 'o', 'r', '_', 'f', 'i', 'l', 'e', 0};
constexpr std::size_t kHeaderBytes = TensorFile::kMagicBytes + 2 + 4;  // magic, version, field count

// Reads the header's integers, or says which part of the header the file ends in.
class HeaderReader {
 public:
  HeaderReader(std::span<const unsigned char> bytes, const std::string& file) : bytes_(bytes), file_(file) {}

  template <class T>
  T take(const std::string& what) {
    T v;
    need(sizeof(T), what);
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string takeText(std::size_t n, const std::string& what) {
    need(n, what);
    std::string s(reinterpret_cast<const char*>(bytes_.data() + pos_), n);
    pos_ += n;
    return s;
  }

 private:
  void need(std::size_t n, const std::string& what) {
    if (bytes_.size() - pos_ < n) {
      throw FileError(file_, "truncated header: the file ends inside " + what + " (at byte " + std::to_string(pos_) +
                                 " of " + std::to_string(bytes_.size()) + ")");
    }
  }
  std::span<const unsigned char> bytes_;
  const std::string& file_;
  std::size_t pos_ = kHeaderBytes;
};

// A field name as a message shows it: printable ASCII, anything else as '?'.
std::string printable(const std::string& name) {
  std::string s = name.substr(0, 64);
  for (char& c : s)
    if (c < 0x20 || c > 0x7e) c = '?';
  return name.size() > 64 ? s + "..." : s;
}

}  // namespace

uint64_t TensorField::elements() const {
  uint64_t n = 1;
  for (uint64_t e : shape) n *= e;
  return n;
}

std::size_t TensorField::elementBytes(Type type) {
  switch (type) {
    case Type::UInt8:
    case Type::Int8: return 1;
    case Type::UInt16:
    case Type::Int16:
    case Type::Float16: return 2;
    case Type::UInt32:
    case Type::Int32:
    case Type::Float32: return 4;
    case Type::UInt64:
    case Type::Int64:
    case Type::Float64: return 8;
  }
  return 0;
}

const char* TensorField::typeName(Type type) {
  static constexpr const char* kNames[] = {"uint8",  "int8",  "uint16",  "int16",   "uint32", "int32",
                                           "uint64", "int64", "float16", "float32", "float64"};
  const auto code = static_cast<unsigned>(type);
  return code >= 1 && code <= 11 ? kNames[code - 1] : "unknown";
}

TensorField TensorField::floats(std::vector<uint64_t> shape, std::span<const float> values) {
  TensorField f{Type::Float32, std::move(shape), {}};
  f.data.resize(values.size_bytes());
  std::memcpy(f.data.data(), values.data(), values.size_bytes());
  return f;
}

TensorField TensorField::bytes(std::vector<uint64_t> shape, std::span<const unsigned char> values) {
  return {Type::UInt8, std::move(shape), {values.begin(), values.end()}};
}

bool TensorFile::hasMagic(std::span<const unsigned char> head) {
  return head.size() >= kMagicBytes && std::memcmp(head.data(), kMagic, kMagicBytes) == 0;
}

TensorFile TensorFile::parse(std::span<const unsigned char> bytes, const std::string& file) {
  if (!hasMagic(bytes)) throw FileError(file, "not a tensor file (an RGL .bsdf starts with \"tensor_file\\0\")");
  if (bytes.size() < kHeaderBytes)
    throw FileError(file, "truncated header: " + std::to_string(bytes.size()) + " bytes, the header alone is 18");
  if (bytes[12] != 1 || bytes[13] != 0) {
    throw FileError(file, "tensor file version " + std::to_string(bytes[12]) + "." + std::to_string(bytes[13]) +
                              ", only 1.0 is supported");
  }
  uint32_t count;
  std::memcpy(&count, bytes.data() + 14, sizeof count);
  // Each field's header takes at least 13 bytes: a count beyond that is a corrupt file, refused
  // before reserving anything for it.
  if (count > (bytes.size() - kHeaderBytes) / 13) {
    throw FileError(file, "header claims " + std::to_string(count) + " fields, more than its " +
                              std::to_string(bytes.size()) + " bytes can describe");
  }
  TensorFile result;
  std::vector<std::pair<uint64_t, uint64_t>> extents;  // offset and bytes of each field's data
  HeaderReader in(bytes, file);
  for (uint32_t i = 0; i < count; ++i) {
    const std::string where = "the header of field " + std::to_string(i);
    const auto nameLength = in.take<uint16_t>(where);
    const std::string name = in.takeText(nameLength, where);
    const std::string field = "field '" + printable(name) + "'";
    const auto ndim = in.take<uint16_t>(where);
    const auto code = in.take<uint8_t>(where);
    const auto offset = in.take<uint64_t>(where);
    if (ndim > TensorField::kMaxDims) {
      throw FileError(file, field + " has " + std::to_string(ndim) + " dimensions, at most " +
                                std::to_string(TensorField::kMaxDims) + " are supported");
    }
    if (code < 1 || code > 11) throw FileError(file, field + " has an unknown dtype code " + std::to_string(code));
    TensorField f;
    f.type = static_cast<TensorField::Type>(code);
    const std::size_t elementBytes = TensorField::elementBytes(f.type);
    uint64_t size = elementBytes;  // bytes, checked against overflow extent by extent
    for (uint16_t d = 0; d < ndim; ++d) {
      const auto extent = in.take<uint64_t>(where);
      if (extent != 0 && size > std::numeric_limits<uint64_t>::max() / extent)
        size = std::numeric_limits<uint64_t>::max();
      else
        size *= extent;
      f.shape.push_back(extent);
    }
    if (result.find(name)) throw FileError(file, field + " appears twice");
    result.fields_.emplace_back(name, std::move(f));
    extents.push_back({offset, size});
  }
  // The data only once the whole header has been read, so a cut header reads as one.
  for (std::size_t i = 0; i < count; ++i) {
    const auto [offset, size] = extents[i];
    TensorField& f = result.fields_[i].second;
    const std::string field = "field '" + printable(result.fields_[i].first) + "'";
    if (offset > bytes.size() || size > bytes.size() - offset) {
      throw FileError(file, field + " (" + TensorField::typeName(f.type) + ", " + std::to_string(f.elements()) +
                                " elements at offset " + std::to_string(offset) +
                                ") lies beyond the end of the file (" + std::to_string(bytes.size()) + " bytes)");
    }
    f.data.assign(bytes.begin() + static_cast<std::ptrdiff_t>(offset),
                  bytes.begin() + static_cast<std::ptrdiff_t>(offset + size));
  }
  return result;
}

TensorFile TensorFile::load(const std::filesystem::path& path) {
  const std::string name = path.string();
  if (const auto problem = regularFileProblem(path)) throw FileError(name, *problem);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(name, std::string("cannot open file (") + std::strerror(errno) + ")");
  in.seekg(0, std::ios::end);
  const std::streamoff end = in.tellg();
  in.seekg(0, std::ios::beg);
  if (end < 0 || !in) throw FileError(name, "cannot determine the file size");
  if (end == 0) throw FileError(name, "file is empty");
  std::vector<unsigned char> bytes(static_cast<std::size_t>(end));
  in.read(reinterpret_cast<char*>(bytes.data()), end);
  if (in.gcount() != end) throw FileError(name, "read error (file changed while reading?)");
  return parse(bytes, name);
}

void TensorFile::add(std::string name, TensorField field) {
  if (find(name)) throw std::invalid_argument("tensor file: field '" + name + "' added twice");
  if (name.size() > std::numeric_limits<uint16_t>::max())
    throw std::invalid_argument("tensor file: field name too long");
  if (field.shape.size() > TensorField::kMaxDims) throw std::invalid_argument("tensor file: too many dimensions");
  if (field.data.size() != field.elements() * TensorField::elementBytes(field.type))
    throw std::invalid_argument("tensor file: field '" + name + "' has data that does not match its shape");
  fields_.emplace_back(std::move(name), std::move(field));
}

const TensorField* TensorFile::find(const std::string& name) const {
  for (const auto& [n, f] : fields_)
    if (n == name) return &f;
  return nullptr;
}

std::vector<unsigned char> TensorFile::serialize() const {
  std::vector<unsigned char> out(kMagic, kMagic + kMagicBytes);
  const auto put = [&](const auto& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    out.insert(out.end(), p, p + sizeof v);
  };
  out.push_back(1);
  out.push_back(0);
  put(static_cast<uint32_t>(fields_.size()));
  std::size_t headerBytes = out.size();
  for (const auto& [name, f] : fields_) headerBytes += 2 + name.size() + 2 + 1 + 8 + 8 * f.shape.size();
  const auto align = [](std::size_t n) { return (n + 7) / 8 * 8; };
  std::size_t offset = align(headerBytes);
  for (const auto& [name, f] : fields_) {
    put(static_cast<uint16_t>(name.size()));
    out.insert(out.end(), name.begin(), name.end());
    put(static_cast<uint16_t>(f.shape.size()));
    put(static_cast<uint8_t>(f.type));
    put(static_cast<uint64_t>(offset));
    for (uint64_t e : f.shape) put(e);
    offset = align(offset + f.data.size());
  }
  for (const auto& [name, f] : fields_) {
    out.resize(align(out.size()), 0);
    out.insert(out.end(), f.data.begin(), f.data.end());
  }
  return out;
}

void TensorFile::save(const std::filesystem::path& path) const {
  const std::vector<unsigned char> bytes = serialize();
  writeFileAtomically(path.string(), std::as_bytes(std::span(bytes)));
}

}  // namespace acdf
