// Saved environment tables: a table rebuilt from serialize() samples bit for bit like the
// original (every cascade strategy, a fallen-back compensation), mismatched or corrupt tables
// throw SerializationError, the key follows the pixels and every table option, and
// EnvironmentTable::cached builds once and loads afterwards.

#include <gtest/gtest.h>

#include <bit>
#include <set>
#include <string>
#include <vector>

#include "acdf/envmap/environment_table.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/table_cache.h"
#include "acdf/test_support/option_variants.h"
#include "app_test_util.h"
#include "envmap_test_util.h"

namespace {

using namespace acdf;
using namespace acdf::envmaptest;

uint64_t bitsOf(double v) { return std::bit_cast<uint64_t>(v); }

void expectSameTable(const EnvironmentTable& a, const EnvironmentTable& b) {
  ASSERT_EQ(a.serialize(), b.serialize());
  EXPECT_EQ(a.bytes(), b.bytes());
  EXPECT_EQ(a.compensationFellBack(), b.compensationFellBack());
  EXPECT_EQ(a.tabulated(), b.tabulated());
  Pcg32 rng(3);
  for (int i = 0; i < 2000; ++i) {
    const float u0 = i == 0 ? 0.0f : rng.nextFloat(), u1 = i == 0 ? kOneMinusEpsilon : rng.nextFloat();
    const EnvironmentTable::Sample s = a.sample(u0, u1), t = b.sample(u0, u1);
    ASSERT_EQ(bitsOf(s.pdf), bitsOf(t.pdf)) << i;
    ASSERT_EQ(s.pixel, t.pixel);
    ASSERT_EQ(bitsOf(s.direction.x), bitsOf(t.direction.x));
    ASSERT_EQ(bitsOf(s.direction.y), bitsOf(t.direction.y));
    ASSERT_EQ(bitsOf(s.direction.z), bitsOf(t.direction.z));
    ASSERT_EQ(bitsOf(a.pdf(s.direction)), bitsOf(b.pdf(s.direction)));
  }
}

TEST(EnvironmentTable, RoundTripsAreBitIdentical) {
  const auto map = smoothMap(64, 32);
  for (EnvironmentTableStrategy s :
       {EnvironmentTableStrategy::Uniform, EnvironmentTableStrategy::Adaptive, EnvironmentTableStrategy::Compensated}) {
    SCOPED_TRACE(std::string(toString(s)));
    const EnvironmentTable built(map, s);
    const std::vector<std::byte> saved = built.serialize();
    ASSERT_FALSE(saved.empty());
    expectSameTable(built, EnvironmentTable(map, s, {}, saved));
  }
  // A constant map's compensation falls back to the plain adaptive table.
  const auto constant = constantMap(32, 16, 2.0f);
  const EnvironmentTable fellBack(constant, EnvironmentTableStrategy::Compensated);
  ASSERT_TRUE(fellBack.compensationFellBack());
  expectSameTable(fellBack, EnvironmentTable(constant, EnvironmentTableStrategy::Compensated, {}, fellBack.serialize()));
}

TEST(EnvironmentTable, StrategiesWithoutACascadeSaveNothing) {
  const auto map = smoothMap(16, 8);
  for (EnvironmentTableStrategy s :
       {EnvironmentTableStrategy::UniformSphere, EnvironmentTableStrategy::Alias, EnvironmentTableStrategy::Hierarchical}) {
    const EnvironmentTable table(map, s);
    EXPECT_TRUE(table.serialize().empty());
    expectSameTable(table, EnvironmentTable(map, s, {}, std::span<const std::byte>{}));
  }
  const EnvironmentTable black(constantMap(16, 8, 0.0f), EnvironmentTableStrategy::Adaptive);
  EXPECT_TRUE(black.serialize().empty());
}

std::string problemOf(const std::shared_ptr<const EnvironmentMap>& map, EnvironmentTableStrategy strategy,
                      const SimplifyOptions& simplify, std::span<const std::byte> saved) {
  try {
    EnvironmentTable table(map, strategy, simplify, saved);
  } catch (const SerializationError& e) {
    return e.what();
  }
  return "";
}

TEST(EnvironmentTable, MismatchedOrCorruptTablesThrow) {
  const auto map = smoothMap(32, 16);
  constexpr EnvironmentTableStrategy adaptive = EnvironmentTableStrategy::Adaptive;
  const std::vector<std::byte> table = EnvironmentTable(map, adaptive).serialize();
  EXPECT_NE(problemOf(smoothMap(16, 16), adaptive, {}, table).find("another map size or other options"),
            std::string::npos);
  EXPECT_NE(problemOf(map, EnvironmentTableStrategy::Uniform, {}, table).find("other options"), std::string::npos);
  SimplifyOptions finer;
  finer.epsilon *= 0.5;
  EXPECT_NE(problemOf(map, adaptive, finer, table).find("other options"), std::string::npos);
  EXPECT_NE(problemOf(map, EnvironmentTableStrategy::Alias, {}, table).find("has none"), std::string::npos);
  EXPECT_NE(problemOf(map, EnvironmentTableStrategy::UniformSphere, {}, table).find("has none"), std::string::npos);
  EXPECT_NE(problemOf(map, adaptive, {}, std::span(table).first(table.size() / 2)).find("truncated"),
            std::string::npos);
  EXPECT_NE(problemOf(map, adaptive, {}, {}).find("truncated"), std::string::npos);
}

TEST(EnvironmentTable, KeyFollowsPixelsAndEveryTableOption) {
  const auto map = smoothMap(32, 16);
  constexpr EnvironmentTableStrategy base = EnvironmentTableStrategy::Adaptive;
  std::set<std::string> keys{EnvironmentTable::key(*map, base, {}).hex()};
  auto add = [&](const EnvironmentMap& m, EnvironmentTableStrategy strategy, const SimplifyOptions& simplify) {
    EXPECT_TRUE(keys.insert(EnvironmentTable::key(m, strategy, simplify).hex()).second);
  };
  for (EnvironmentTableStrategy s : kEnvironmentTableStrategies)
    if (s != base) add(*map, s, {});
  for (const SimplifyOptions& s : test_support::simplifyVariants(SimplifyOptions{})) add(*map, base, s);
  // The pixels: one channel of one pixel, and the same pixels in another shape.
  std::vector<float> rgb = map->rgb();
  rgb[3 * 77 + 2] = std::nextafter(rgb[3 * 77 + 2], 10.0f);
  add(EnvironmentMap(32, 16, rgb), base, {});
  add(EnvironmentMap(16, 32, map->rgb()), base, {});
}

class EnvironmentTableCache : public apptest::TempDirTest {};

TEST_F(EnvironmentTableCache, CachedBuildsOnceThenLoads) {
  std::vector<std::string> warnings;
  TableCache cache(dir_ / "cache", [&](const std::string& w) { warnings.push_back(w); });
  const auto map = smoothMap(64, 32);
  constexpr EnvironmentTableStrategy adaptive = EnvironmentTableStrategy::Adaptive;
  const Cached<EnvironmentTable> first = EnvironmentTable::cached(cache, map, adaptive, {}, "sky");
  const Cached<EnvironmentTable> second = EnvironmentTable::cached(cache, map, adaptive, {}, "sky");
  EXPECT_FALSE(first.fromCache);
  EXPECT_TRUE(second.fromCache);
  expectSameTable(first.value, second.value);
  // Strategies whose table is not worth saving are built, and leave nothing in the cache.
  const std::size_t files = std::distance(std::filesystem::directory_iterator(dir_ / "cache"), {});
  for (EnvironmentTableStrategy s :
       {EnvironmentTableStrategy::UniformSphere, EnvironmentTableStrategy::Alias, EnvironmentTableStrategy::Hierarchical})
    EXPECT_FALSE(EnvironmentTable::cached(cache, map, s, {}, "sky").fromCache);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_ / "cache"), {}), files);
  EXPECT_TRUE(warnings.empty());
}

}  // namespace
