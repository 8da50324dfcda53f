#pragma once
// An on-disk cache of built sampling tables (docs/table-cache.md), so a renderer builds an
// expensive table once per input and set of options, not once per run.
//
// Key: a 128-bit ContentHash of the table's input (pixels, BRDF values), a text naming the table
// kind and every parameter that shapes it, and kTableCacheFormatVersion (cacheKey()). Value: an
// opaque payload (e.g. Cascade::serialize()). One file per key, <directory>/<32 hex digits>.table:
//   8 bytes  magic "ACDFTBL\n"
//   u32      kTableCacheFormatVersion
//   16 bytes the key (high, low; u64 little-endian each)
//   u64      payload size
//   16 bytes ContentHash of the payload (the checksum)
//   payload
// A file is trusted only if all of that matches and its size is exactly header + payload; anything
// else is a rejected file (reported, then treated as a miss and overwritten by the next store).
// store() writes a uniquely named temporary file in the same directory and renames it over the
// final name, so processes sharing the directory see the old file, the new one, or none, never
// a partial one. A directory that cannot be created or written gives one warning and turns
// storing off for this cache object: caching never makes a run fail.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "acdf/sampling/byte_io.h"
#include "acdf/sampling/cascade.h"

namespace acdf {

// Bumped whenever the file layout above changes, or libsampling builds the same input into a
// different table (2: every cell of positive mass keeps a positive CDF step), so that no table of
// an older build is reused; part of every key and of every file header.
inline constexpr uint32_t kTableCacheFormatVersion = 2;

struct CacheKey {
  uint64_t high = 0, low = 0;
  // 32 lowercase hex digits (high first): the file's name.
  std::string hex() const;
  bool operator==(const CacheKey&) const = default;
};

// A streaming, non-cryptographic 128-bit hash. Two 64-bit lanes each take every 8-byte word w
// (little-endian; a short last word is zero-padded) as h ← (rotl(h, r) ⊕ w) · P with an odd P:
// a bijection of h for fixed w and of w for fixed h, so two inputs of equal length that differ
// in one word always differ after it, and later words keep them apart. The total length is mixed
// into the final avalanche (MurmurHash3's fmix64), so zero padding cannot collide either. At one
// multiply per lane per 8 bytes it is several times faster than byte-wise FNV-1a
// (docs/table-cache.md gives the figures), and 128 bits make an accidental key collision
// (which would load another table) negligible however many tables a cache holds. Not for
// adversarial input.
class ContentHash {
 public:
  ContentHash& bytes(std::span<const std::byte> data);
  template <class T>
  ContentHash& values(std::span<const T> data) {
    static_assert(std::is_trivially_copyable_v<T>, "hashes the values' bytes");
    return bytes(std::as_bytes(data));
  }
  // Length first, so ("ab", "c") and ("a", "bc") differ.
  ContentHash& text(std::string_view s);
  ContentHash& number(uint64_t v);

  CacheKey digest() const;

 private:
  void word(uint64_t w);

  uint64_t a_ = 0x243f6a8885a308d3ull, b_ = 0x13198a2e03707344ull;  // digits of π: any fixed values
  uint64_t pending_ = 0;                                            // bytes not yet forming a whole word, little-endian
  unsigned pendingBytes_ = 0;
  uint64_t length_ = 0;
};

// The key of a table: `content` the hash of its input; `parameters` the table kind, every option
// that shapes the table, and the version of its payload's format, as text (e.g. "envmap-light
// cascade-v1 strategy=adaptive epsilon=0x1.0624dd2f1a9fcp-9 ..."; hex floats keep doubles exact).
CacheKey cacheKey(const ContentHash& content, std::string_view parameters);

// Exact text of the options that shape a Cascade, for parameter strings.
std::string describe(const CascadeOptions& options);
std::string describe(const SimplifyOptions& options);

enum class CacheStatus : uint8_t {
  Hit,       // payload holds the stored bytes
  Miss,      // no file for the key
  Rejected,  // a file exists but fails a check; problem says which (it is not used)
  Disabled,  // a cache without a directory (--no-cache)
};

struct CacheRead {
  CacheStatus status = CacheStatus::Miss;
  std::vector<std::byte> payload;
  std::string problem;  // Rejected: "<file>: <what is wrong>", one line
};

// A value from TableCache::getOrBuild and whether it was read from the cache or built.
template <class T>
struct Cached {
  T value;
  bool fromCache = false;
};

class TableCache {
 public:
  // Receives every warning (a rejected file, a failed store), one line each. Called from the
  // thread that calls load/store/getOrBuild.
  using Warn = std::function<void(const std::string&)>;

  // A cache in `directory` (created on the first store). No warning callback: warnings dropped.
  explicit TableCache(std::filesystem::path directory, Warn warn = {});
  // A cache that neither loads nor stores (--no-cache): every getOrBuild builds.
  static TableCache disabled();
  // $XDG_CACHE_HOME/acdf if that variable holds an absolute path, else $HOME/.cache/acdf; none
  // when neither is usable.
  static std::optional<std::filesystem::path> defaultDirectory();
  // A cache in defaultDirectory(), or a disabled one (with a warning) when there is none.
  static TableCache atDefaultLocation(Warn warn = {});

  bool enabled() const { return !directory_.empty(); }
  const std::filesystem::path& directory() const { return directory_; }
  std::filesystem::path fileOf(const CacheKey& key) const;

  // Reads and checks the file of `key`. Never throws for a bad or unreadable file (Rejected).
  CacheRead load(const CacheKey& key) const;
  // Writes the payload for `key` (temporary file + rename). Returns false, after a warning, if
  // that failed; the first failure turns storing off for this object (one warning per run).
  bool store(const CacheKey& key, std::span<const std::byte> payload);

  // The value for `key`: deserialize(payload) if the cache holds a valid one, else build() and
  // store serialize(value). A rejected file, or a payload that deserialize() rejects by throwing
  // SerializationError, is reported through the warning callback ("<what>: <problem>;
  // rebuilding") and rebuilt. `what` names the table for messages, e.g. "BRDF table nickel".
  template <class Build, class Serialize, class Deserialize>
  auto getOrBuild(const CacheKey& key, std::string_view what, Build&& build, Serialize&& serialize,
                  Deserialize&& deserialize) -> Cached<std::invoke_result_t<Build>> {
    using T = std::invoke_result_t<Build>;
    const CacheRead read = load(key);
    if (read.status == CacheStatus::Hit) {
      try {
        return Cached<T>{deserialize(std::span<const std::byte>(read.payload)), true};
      } catch (const SerializationError& e) {
        warn(std::string(what) + ": " + fileOf(key).string() + ": " + e.what() + "; rebuilding");
      }
    } else if (read.status == CacheStatus::Rejected) {
      warn(std::string(what) + ": " + read.problem + "; rebuilding");
    }
    Cached<T> built{build(), false};
    if (storing()) store(key, serialize(built.value));
    return built;
  }
  // The same for a Cascade, with its own serialization.
  Cached<Cascade> getOrBuild(const CacheKey& key, std::string_view what, const std::function<Cascade()>& build);

 private:
  bool storing() const { return enabled() && !storeFailed_->load(); }
  void warn(const std::string& message) const {
    if (warn_) warn_(message);
  }

  std::filesystem::path directory_;  // empty: disabled
  Warn warn_;
  std::unique_ptr<std::atomic<bool>> storeFailed_ = std::make_unique<std::atomic<bool>>(false);
};

}  // namespace acdf
