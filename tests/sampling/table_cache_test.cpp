// TableCache: the content hash, keys, store/load round trips, rejected files (truncated, a
// changed byte anywhere, another format version, another key), concurrent stores of one key,
// an unwritable directory, the default location, and getOrBuild's build / load / rebuild paths.

#include "acdf/sampling/table_cache.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "acdf/sampling/rng.h"
#include "acdf/test_support/option_variants.h"

namespace {

using namespace acdf;
namespace fs = std::filesystem;

std::vector<std::byte> bytesOf(std::string_view s) {
  const auto b = std::as_bytes(std::span<const char>(s.data(), s.size()));
  return {b.begin(), b.end()};
}

std::vector<std::byte> randomBytes(std::size_t n, uint64_t seed) {
  Pcg32 rng(seed);
  std::vector<std::byte> out(n);
  for (std::byte& b : out) b = static_cast<std::byte>(rng.nextUint());
  return out;
}

std::vector<std::byte> readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> raw((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto b = std::as_bytes(std::span<const char>(raw));
  return {b.begin(), b.end()};
}

void writeFile(const fs::path& path, std::span<const std::byte> bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// A fresh directory per test, removed afterwards.
class TableCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("acdf-table-cache-test-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  TableCache cache() {
    return TableCache(dir_, [this](const std::string& w) { warnings_.push_back(w); });
  }
  std::vector<fs::path> filesInDir() const {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir_)) files.push_back(e.path());
    return files;
  }

  // getOrBuild of a small cascade under kKey, counting the builds.
  Cached<Cascade> getSmallTable(TableCache& c);

  fs::path dir_;
  std::vector<std::string> warnings_;
  int builds_ = 0;
};

const CacheKey kKey = cacheKey(ContentHash().text("input"), "kind=test");

// ---- Hash and keys ------------------------------------------------------------------------

TEST(ContentHashTest, PiecewiseFeedingEqualsOneCall) {
  const std::vector<std::byte> data = randomBytes(1000, 1);
  const CacheKey whole = ContentHash().bytes(data).digest();
  for (std::size_t split : {0u, 1u, 7u, 8u, 9u, 13u, 500u, 999u}) {
    ContentHash h;
    h.bytes(std::span(data).first(split));
    h.bytes(std::span(data).subspan(split, 3 > data.size() - split ? data.size() - split : 3));
    h.bytes(std::span(data).subspan(std::min(split + 3, data.size())));
    EXPECT_EQ(h.digest(), whole) << split;
  }
}

TEST(ContentHashTest, EveryBitOfTheInputChangesTheDigest) {
  const std::vector<std::byte> data = randomBytes(64, 2);
  std::set<std::pair<uint64_t, uint64_t>> digests{
      {ContentHash().bytes(data).digest().high, ContentHash().bytes(data).digest().low}};
  for (std::size_t i = 0; i < data.size() * 8; ++i) {
    std::vector<std::byte> changed = data;
    changed[i / 8] ^= std::byte{static_cast<uint8_t>(1u << (i % 8))};
    const CacheKey k = ContentHash().bytes(changed).digest();
    digests.insert({k.high, k.low});
  }
  EXPECT_EQ(digests.size(), data.size() * 8 + 1);
}

TEST(ContentHashTest, LengthAndSeparationMatter) {
  // Zero padding of the last word, and where one text ends and the next begins.
  EXPECT_NE(ContentHash().bytes(bytesOf("a")).digest(), ContentHash().bytes(bytesOf(std::string("a\0", 2))).digest());
  EXPECT_NE(ContentHash().digest(), ContentHash().bytes(bytesOf(std::string(1, '\0'))).digest());
  EXPECT_NE(ContentHash().text("ab").text("c").digest(), ContentHash().text("a").text("bc").digest());
  EXPECT_NE(ContentHash().number(1).digest(), ContentHash().number(2).digest());
}

TEST(CacheKeyTest, DependsOnContentAndParametersAndPrintsAsHex) {
  const CacheKey a = cacheKey(ContentHash().text("pixels"), "strategy=adaptive");
  EXPECT_EQ(a, cacheKey(ContentHash().text("pixels"), "strategy=adaptive"));
  EXPECT_NE(a, cacheKey(ContentHash().text("pixelz"), "strategy=adaptive"));
  EXPECT_NE(a, cacheKey(ContentHash().text("pixels"), "strategy=uniform"));
  EXPECT_EQ(a.hex().size(), 32u);
  EXPECT_EQ(a.hex().find_first_not_of("0123456789abcdef"), std::string::npos);
  EXPECT_EQ((CacheKey{0x0123456789abcdefull, 0xfull}.hex()), "0123456789abcdef000000000000000f");
}

TEST(CacheKeyTest, DescribeNamesEveryCascadeOption) {
  // Every field change shows in the text, so it changes any key built from it.
  const CascadeOptions base;
  std::vector<CascadeOptions> variants(4, base);
  variants[0].conditioningDims = 1;
  variants[1].methods = {DimensionMethod::Uniform};
  variants[2].conditional = ConditionalRule::AverageOfNormalized;
  variants[3].tolerance = ConditionalTolerance::MassScaled;
  CascadeOptions grouped = base;
  grouped.sliceGroupingTolerance = 1e-3;
  variants.push_back(grouped);
  for (const SimplifyOptions& s : test_support::simplifyVariants(base.simplify)) {
    variants.push_back(base);
    variants.back().simplify = s;
  }
  std::set<std::string> texts{describe(base)};
  for (const CascadeOptions& v : variants) texts.insert(describe(v));
  EXPECT_EQ(texts.size(), variants.size() + 1);
}

// ---- Store and load -----------------------------------------------------------------------

TEST_F(TableCacheTest, MissThenStoreThenHit) {
  TableCache c = cache();
  EXPECT_EQ(c.load(kKey).status, CacheStatus::Miss);
  const std::vector<std::byte> payload = randomBytes(5000, 3);
  ASSERT_TRUE(c.store(kKey, payload));
  const CacheRead r = c.load(kKey);
  ASSERT_EQ(r.status, CacheStatus::Hit) << r.problem;
  EXPECT_EQ(r.payload, payload);
  EXPECT_EQ(c.fileOf(kKey), dir_ / (kKey.hex() + ".table"));
  EXPECT_EQ(filesInDir(), std::vector<fs::path>{c.fileOf(kKey)});  // no temporary left behind
  EXPECT_TRUE(warnings_.empty());
  // An empty payload is a valid value too.
  const CacheKey other = cacheKey(ContentHash(), "empty");
  ASSERT_TRUE(c.store(other, {}));
  EXPECT_EQ(c.load(other).status, CacheStatus::Hit);
}

TEST_F(TableCacheTest, RejectsTruncatedChangedWrongVersionAndWrongKeyFiles) {
  TableCache c = cache();
  const std::vector<std::byte> payload = randomBytes(300, 4);
  ASSERT_TRUE(c.store(kKey, payload));
  const fs::path path = c.fileOf(kKey);
  const std::vector<std::byte> good = readFile(path);
  constexpr std::size_t kHeader = 52;  // magic 8, version 4, key 16, size 8, checksum 16
  ASSERT_EQ(good.size(), kHeader + payload.size());

  auto expectRejected = [&](const std::vector<std::byte>& bytes, const std::string& fragment) {
    writeFile(path, bytes);
    const CacheRead r = c.load(kKey);
    EXPECT_EQ(r.status, CacheStatus::Rejected) << fragment;
    EXPECT_TRUE(r.payload.empty());
    EXPECT_EQ(r.problem.rfind(path.string() + ": ", 0), 0u) << r.problem;
    EXPECT_NE(r.problem.find(fragment), std::string::npos) << "'" << r.problem << "' lacks '" << fragment << "'";
    EXPECT_EQ(r.problem.find('\n'), std::string::npos);
  };
  for (std::size_t n : {std::size_t{0}, std::size_t{7}, kHeader - 1}) {
    expectRejected(std::vector<std::byte>(good.begin(), good.begin() + n), "truncated");
  }
  for (std::size_t n : {kHeader, kHeader + 1, good.size() - 1}) {
    expectRejected(std::vector<std::byte>(good.begin(), good.begin() + n), "truncated or overwritten");
  }
  std::vector<std::byte> longer = good;
  longer.push_back(std::byte{0});
  expectRejected(longer, "truncated or overwritten");

  std::vector<std::byte> b = good;
  b[8] = std::byte{kTableCacheFormatVersion + 1};
  expectRejected(b, "cache format version " + std::to_string(kTableCacheFormatVersion + 1) + ", this build uses " +
                        std::to_string(kTableCacheFormatVersion));
  b = good;
  b[0] = std::byte{'X'};
  expectRejected(b, "wrong magic number");
  // Every single changed byte is caught, by the header checks or the payload checksum.
  for (std::size_t i = 0; i < good.size(); ++i) {
    b = good;
    b[i] ^= std::byte{0x10};
    writeFile(path, b);
    EXPECT_EQ(c.load(kKey).status, CacheStatus::Rejected) << "byte " << i;
  }
  b = good;
  b[kHeader + 17] ^= std::byte{1};
  expectRejected(b, "checksum mismatch");
  // Another key's file under this key's name (a renamed or copied file).
  const CacheKey other = cacheKey(ContentHash().text("other"), "kind=test");
  ASSERT_TRUE(c.store(other, payload));
  fs::copy_file(c.fileOf(other), path, fs::copy_options::overwrite_existing);
  expectRejected(readFile(path), "holds the table of key " + other.hex());
  fs::remove(path);
  fs::create_directory(path);
  const CacheRead directory = c.load(kKey);
  EXPECT_EQ(directory.status, CacheStatus::Rejected);
  EXPECT_NE(directory.problem.find("not a regular file"), std::string::npos) << directory.problem;
  EXPECT_TRUE(warnings_.empty());  // load reports through its status; getOrBuild warns
}

TEST_F(TableCacheTest, ConcurrentStoresOfOneKeyNeverExposeAPartialFile) {
  // Writers store different 256 KB payloads under one key while a reader polls it: the reader
  // sees nothing or one complete payload, never a rejected file.
  TableCache c = cache();
  constexpr int kWriters = 4, kRounds = 6;
  std::vector<std::vector<std::byte>> payloads;
  for (int w = 0; w < kWriters; ++w) payloads.push_back(randomBytes(256 * 1024, 10 + w));
  std::atomic<bool> done{false};
  std::atomic<int> bad{0};
  std::thread reader([&] {
    while (!done) {
      const CacheRead r = c.load(kKey);
      if (r.status == CacheStatus::Hit) {
        if (std::find(payloads.begin(), payloads.end(), r.payload) == payloads.end()) ++bad;
      } else if (r.status != CacheStatus::Miss) {
        ++bad;
      }
    }
  });
  std::vector<std::thread> writers;
  std::atomic<int> stored{0};
  for (int w = 0; w < kWriters; ++w) {
    writers.emplace_back([&, w] {
      for (int i = 0; i < kRounds; ++i) stored += c.store(kKey, payloads[w]);
    });
  }
  for (std::thread& t : writers) t.join();
  done = true;
  reader.join();
  EXPECT_EQ(stored, kWriters * kRounds);
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(c.load(kKey).status, CacheStatus::Hit);
  EXPECT_EQ(filesInDir().size(), 1u);  // every temporary was renamed
  EXPECT_TRUE(warnings_.empty());
}

TEST_F(TableCacheTest, UnwritableDirectoryWarnsOnceAndNeverFails) {
  // A directory below a regular file can never be created (whatever the user's privileges).
  fs::create_directories(dir_);
  writeFile(dir_ / "file", bytesOf("x"));
  TableCache c(dir_ / "file" / "acdf", [this](const std::string& w) { warnings_.push_back(w); });
  EXPECT_EQ(c.load(kKey).status, CacheStatus::Miss);
  EXPECT_FALSE(c.store(kKey, bytesOf("payload")));
  EXPECT_FALSE(c.store(kKey, bytesOf("payload")));
  ASSERT_EQ(warnings_.size(), 1u);
  EXPECT_NE(warnings_[0].find("cannot create"), std::string::npos) << warnings_[0];
  EXPECT_NE(warnings_[0].find("not cached"), std::string::npos) << warnings_[0];
  int builds = 0;
  for (int i = 0; i < 2; ++i) {
    const Cached<int> v = c.getOrBuild(
        kKey, "test table", [&] { return ++builds; }, [](int) { return bytesOf("v"); },
        [](std::span<const std::byte>) { return 0; });
    EXPECT_FALSE(v.fromCache);
  }
  EXPECT_EQ(builds, 2);
  EXPECT_EQ(warnings_.size(), 1u);
}

TEST_F(TableCacheTest, DisabledCacheAlwaysBuilds) {
  TableCache c = TableCache::disabled();
  EXPECT_FALSE(c.enabled());
  EXPECT_EQ(c.load(kKey).status, CacheStatus::Disabled);
  EXPECT_FALSE(c.store(kKey, bytesOf("x")));
  const Cached<Cascade> t = c.getOrBuild(kKey, "t", [] {
    const float v[3] = {1, 2, 3};
    return Cascade(v, {GridAxis(3)});
  });
  EXPECT_FALSE(t.fromCache);
  EXPECT_FALSE(fs::exists(dir_));
}

// ---- getOrBuild ---------------------------------------------------------------------------

Cascade smallTable() {
  std::vector<float> v(24 * 16);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<float>(1.0 + std::sin(0.37 * i));
  return Cascade(v, {GridAxis(24), GridAxis(16)});
}

Cached<Cascade> TableCacheTest::getSmallTable(TableCache& c) {
  return c.getOrBuild(kKey, "test table", [this] {
    ++builds_;
    return smallTable();
  });
}

TEST_F(TableCacheTest, GetOrBuildBuildsOnceThenLoadsAnIdenticalTable) {
  TableCache c = cache();
  const Cached<Cascade> first = getSmallTable(c);
  const Cached<Cascade> second = getSmallTable(c);
  EXPECT_FALSE(first.fromCache);
  EXPECT_TRUE(second.fromCache);
  EXPECT_EQ(builds_, 1);
  EXPECT_EQ(first.value.serialize(), second.value.serialize());
  const float u[2] = {0.25f, 0.75f};
  EXPECT_EQ(first.value.sample(u).pdf, second.value.sample(u).pdf);
  EXPECT_TRUE(warnings_.empty());
}

TEST_F(TableCacheTest, GetOrBuildRebuildsCorruptFilesWithAWarning) {
  TableCache c = cache();
  getSmallTable(c);
  // A corrupt file: rejected by the cache's checks, rebuilt and overwritten.
  std::vector<std::byte> bytes = readFile(c.fileOf(kKey));
  bytes.back() ^= std::byte{1};
  writeFile(c.fileOf(kKey), bytes);
  EXPECT_FALSE(getSmallTable(c).fromCache);
  ASSERT_EQ(warnings_.size(), 1u);
  EXPECT_EQ(warnings_[0].rfind("test table: " + c.fileOf(kKey).string() + ": payload checksum mismatch", 0), 0u)
      << warnings_[0];
  EXPECT_NE(warnings_[0].find("rebuilding"), std::string::npos);
  EXPECT_TRUE(getSmallTable(c).fromCache);
  // A file whose checks pass but whose payload is no cascade (a bug, or a key collision).
  ASSERT_TRUE(c.store(kKey, bytesOf("not a cascade")));
  EXPECT_FALSE(getSmallTable(c).fromCache);
  ASSERT_EQ(warnings_.size(), 2u);
  EXPECT_NE(warnings_[1].find("cascade: "), std::string::npos) << warnings_[1];
  EXPECT_TRUE(getSmallTable(c).fromCache);
  EXPECT_EQ(builds_, 3);
}

TEST(TableCacheLocation, FollowsXdgCacheHomeThenHome) {
  auto get = [](const char* name) -> std::optional<std::string> {
    const char* v = std::getenv(name);
    return v ? std::optional<std::string>(v) : std::nullopt;
  };
  const std::optional<std::string> xdg = get("XDG_CACHE_HOME"), home = get("HOME");
  ::setenv("XDG_CACHE_HOME", "/xdg/cache", 1);
  ::setenv("HOME", "/home/someone", 1);
  EXPECT_EQ(TableCache::defaultDirectory(), fs::path("/xdg/cache/acdf"));
  ::setenv("XDG_CACHE_HOME", "relative/cache", 1);  // invalid per the XDG specification
  EXPECT_EQ(TableCache::defaultDirectory(), fs::path("/home/someone/.cache/acdf"));
  ::unsetenv("XDG_CACHE_HOME");
  EXPECT_EQ(TableCache::defaultDirectory(), fs::path("/home/someone/.cache/acdf"));
  ::unsetenv("HOME");
  EXPECT_EQ(TableCache::defaultDirectory(), std::nullopt);
  std::vector<std::string> warnings;
  const TableCache c = TableCache::atDefaultLocation([&](const std::string& w) { warnings.push_back(w); });
  EXPECT_FALSE(c.enabled());
  EXPECT_EQ(warnings.size(), 1u);
  if (xdg) ::setenv("XDG_CACHE_HOME", xdg->c_str(), 1);
  if (home) ::setenv("HOME", home->c_str(), 1);
}

}  // namespace
