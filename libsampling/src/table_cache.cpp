#include "acdf/sampling/table_cache.h"
#include "acdf/sampling/file_error.h"
#include "acdf/sampling/write_atomically.h"


#include <algorithm>
#include <array>
#include <bit>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <system_error>
#include <thread>

namespace acdf {

namespace {

// MurmurHash3's 64-bit finaliser: every input bit reaches every output bit.
uint64_t avalanche(uint64_t h) {
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 33;
  return h;
}

constexpr std::array<char, 8> kMagic = {'A', 'C', 'D', 'F', 'T', 'B', 'L', '\n'};
constexpr std::size_t kHeaderBytes = kMagic.size() + 4 + 16 + 8 + 16;

std::string hexFloat(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%a", v);
  return buffer;
}

void putKey(ByteWriter& out, const CacheKey& key) {
  out.put(key.high);
  out.put(key.low);
}

CacheKey getKey(ByteReader& in) {
  CacheKey key;
  key.high = in.get<uint64_t>();
  key.low = in.get<uint64_t>();
  return key;
}

CacheKey checksum(std::span<const std::byte> payload) { return ContentHash().bytes(payload).digest(); }

}  // namespace

std::string CacheKey::hex() const {
  char buffer[33];
  std::snprintf(buffer, sizeof buffer, "%016llx%016llx", static_cast<unsigned long long>(high),
                static_cast<unsigned long long>(low));
  return buffer;
}

void ContentHash::word(uint64_t w) {
  a_ = (std::rotl(a_, 29) ^ w) * 0x9e3779b97f4a7c15ull;
  b_ = (std::rotl(b_, 41) ^ w) * 0xd6e8feb86659fd93ull;
}

ContentHash& ContentHash::bytes(std::span<const std::byte> data) {
  length_ += data.size();
  std::size_t i = 0;
  // Complete a pending partial word first, then whole words, then keep the rest pending.
  for (; i < data.size() && pendingBytes_ != 0; ++i) {
    pending_ |= std::to_integer<uint64_t>(data[i]) << (8 * pendingBytes_);
    if (++pendingBytes_ == 8) {
      word(pending_);
      pending_ = 0;
      pendingBytes_ = 0;
    }
  }
  for (; i + 8 <= data.size(); i += 8) {
    uint64_t w = 0;
    for (unsigned k = 0; k < 8; ++k) w |= std::to_integer<uint64_t>(data[i + k]) << (8 * k);
    word(w);
  }
  for (; i < data.size(); ++i) pending_ |= std::to_integer<uint64_t>(data[i]) << (8 * pendingBytes_++);
  return *this;
}

ContentHash& ContentHash::text(std::string_view s) {
  number(s.size());
  return bytes(std::as_bytes(std::span<const char>(s.data(), s.size())));
}

ContentHash& ContentHash::number(uint64_t v) {
  ByteWriter out;
  out.put(v);
  return bytes(out.bytes());
}

CacheKey ContentHash::digest() const {
  ContentHash last = *this;
  if (last.pendingBytes_ != 0) last.word(last.pending_);  // the zero-padded last word
  const uint64_t high = avalanche(last.a_ ^ length_);
  return {high, avalanche(last.b_ ^ std::rotl(length_, 32) ^ high)};
}

CacheKey cacheKey(const ContentHash& content, std::string_view parameters) {
  const CacheKey input = content.digest();
  return ContentHash()
      .text("acdf table cache")
      .number(kTableCacheFormatVersion)
      .number(input.high)
      .number(input.low)
      .text(parameters)
      .digest();
}

std::string describe(const SimplifyOptions& o) {
  return "simplifier=" + std::string(toString(o.method)) + " metric=" + std::string(toString(o.metric)) +
         " epsilon=" + hexFloat(o.epsilon) + " max-points=" + std::to_string(o.maxPoints) +
         " weight-bound=" + hexFloat(o.weightBound);
}

std::string describe(const CascadeOptions& o) {
  std::string methods;
  for (DimensionMethod m : o.methods) methods += m == DimensionMethod::Uniform ? 'u' : 'a';
  return "conditioning=" + std::to_string(o.conditioningDims) +
         " methods=" + (methods.empty() ? "all-adaptive" : methods) + " " + describe(o.simplify) +
         " conditional=" + std::string(toString(o.conditional)) + " tolerance=" + std::string(toString(o.tolerance)) +
         " slice-grouping=" + hexFloat(o.sliceGroupingTolerance) +
         " cascade-format=" + std::to_string(Cascade::kSerialVersion);
}

TableCache::TableCache(std::filesystem::path directory, Warn warn)
    : directory_(std::move(directory)), warn_(std::move(warn)) {}

TableCache TableCache::disabled() { return TableCache({}); }

std::optional<std::filesystem::path> TableCache::defaultDirectory() {
  // The XDG base directory specification: a relative $XDG_CACHE_HOME is invalid and ignored.
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && std::filesystem::path(xdg).is_absolute()) {
    return std::filesystem::path(xdg) / "acdf";
  }
  if (const char* home = std::getenv("HOME"); home && std::filesystem::path(home).is_absolute()) {
    return std::filesystem::path(home) / ".cache" / "acdf";
  }
  return std::nullopt;
}

TableCache TableCache::atDefaultLocation(Warn warn) {
  if (std::optional<std::filesystem::path> dir = defaultDirectory()) return TableCache(*dir, std::move(warn));
  if (warn) warn("table cache: neither $XDG_CACHE_HOME nor $HOME is an absolute path; tables are not cached");
  return TableCache({}, std::move(warn));
}

std::filesystem::path TableCache::fileOf(const CacheKey& key) const { return directory_ / (key.hex() + ".table"); }

CacheRead TableCache::load(const CacheKey& key) const {
  if (!enabled()) return {CacheStatus::Disabled, {}, {}};
  const std::filesystem::path path = fileOf(key);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return {CacheStatus::Miss, {}, {}};
  auto reject = [&](const std::string& problem) {
    return CacheRead{CacheStatus::Rejected, {}, path.string() + ": " + problem};
  };
  if (!std::filesystem::is_regular_file(path, ec)) return reject("not a regular file");

  // One read of the whole file. A concurrent store renames a new file over the name; the open
  // stream keeps reading the old one, so the size stays right.
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file) return reject("cannot be opened");
  const std::streamoff fileSize = file.tellg();
  if (fileSize < 0) return reject("cannot be read");
  std::vector<char> raw(static_cast<std::size_t>(fileSize));
  file.seekg(0);
  if (!file.read(raw.data(), fileSize)) return reject("read error");
  const std::span<const std::byte> bytes = std::as_bytes(std::span<const char>(raw));
  if (bytes.size() < kHeaderBytes) {
    return reject("truncated (" + std::to_string(bytes.size()) + " bytes, the header alone has " +
                  std::to_string(kHeaderBytes) + ")");
  }
  ByteReader in(bytes, path.string());
  try {
    const std::span<const std::byte> magic = in.getBytes(kMagic.size());
    if (!std::equal(magic.begin(), magic.end(), std::as_bytes(std::span(kMagic)).begin())) {
      return reject("not an acdf table cache file (wrong magic number)");
    }
    if (const uint32_t version = in.get<uint32_t>(); version != kTableCacheFormatVersion) {
      return reject("cache format version " + std::to_string(version) + ", this build uses " +
                    std::to_string(kTableCacheFormatVersion));
    }
    if (const CacheKey stored = getKey(in); stored != key) return reject("holds the table of key " + stored.hex());
    const uint64_t size = in.get<uint64_t>();
    const CacheKey sum = getKey(in);
    if (size != in.remaining()) {
      return reject("payload of " + std::to_string(in.remaining()) + " bytes, the header says " + std::to_string(size) +
                    " (truncated or overwritten)");
    }
    const std::span<const std::byte> payload = in.getBytes(static_cast<std::size_t>(size));
    if (checksum(payload) != sum) return reject("payload checksum mismatch (corrupt file)");
    return {CacheStatus::Hit, std::vector<std::byte>(payload.begin(), payload.end()), {}};
  } catch (const SerializationError& e) {
    return reject(e.what());  // unreachable with the size check above, but never trust a file
  }
}

bool TableCache::store(const CacheKey& key, std::span<const std::byte> payload) {
  if (!storing()) return false;
  auto failed = [&](const std::string& problem) {
    // Only the first failure warns: an unwritable directory would repeat it for every table.
    if (!storeFailed_->exchange(true)) warn("table cache: " + problem + "; tables are not cached in this run");
    return false;
  };
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  if (ec) return failed("cannot create " + directory_.string() + ": " + ec.message());

  const std::filesystem::path path = fileOf(key);
  try {
    writeFileAtomically(path.string(), [&](const std::string& temporary) {
      ByteWriter header;
      header.putBytes(std::as_bytes(std::span(kMagic)));
      header.put(kTableCacheFormatVersion);
      putKey(header, key);
      header.put<uint64_t>(payload.size());
      putKey(header, checksum(payload));
      std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
      file.write(reinterpret_cast<const char*>(header.bytes().data()),
                 static_cast<std::streamsize>(header.bytes().size()));
      file.write(reinterpret_cast<const char*>(payload.data()), static_cast<std::streamsize>(payload.size()));
      file.close();
      if (!file) throw FileError(path.string(), "error writing " + temporary);
    });
  } catch (const FileError& e) {
    return failed(e.what());
  }
  return true;
}

Cached<Cascade> TableCache::getOrBuild(const CacheKey& key, std::string_view what,
                                       const std::function<Cascade()>& build) {
  return getOrBuild(
      key, what, build, [](const Cascade& c) { return c.serialize(); },
      [](std::span<const std::byte> bytes) { return Cascade::deserialize(bytes); });
}

}  // namespace acdf
