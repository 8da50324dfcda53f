// Saved environment-light tables: a light rebuilt from serializeTable() samples and evaluates bit
// for bit like the original (every cascade strategy, a fallen-back compensation), mismatched or
// corrupt tables throw SerializationError, the key follows the pixels and every table option,
// and EnvironmentLight::cached builds once and loads afterwards.

#include <gtest/gtest.h>

#include <bit>
#include <set>
#include <string>
#include <vector>

#include "acdf/envmap/environment_light.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/table_cache.h"
#include "acdf/test_support/option_variants.h"
#include "app_test_util.h"
#include "envmap_test_util.h"

namespace {

using namespace acdf;
using namespace acdf::envmaptest;

EnvironmentLightOptions withStrategy(EnvironmentSampling s) {
  EnvironmentLightOptions o;
  o.strategy = s;
  return o;
}

uint64_t bitsOf(double v) { return std::bit_cast<uint64_t>(v); }

void expectSameLight(const EnvironmentLight& a, const EnvironmentLight& b) {
  ASSERT_EQ(a.serializeTable(), b.serializeTable());
  EXPECT_EQ(a.tableBytes(), b.tableBytes());
  EXPECT_EQ(a.compensationFellBack(), b.compensationFellBack());
  EXPECT_EQ(a.tabulated(), b.tabulated());
  Pcg32 rng(3);
  for (int i = 0; i < 2000; ++i) {
    const float u0 = i == 0 ? 0.0f : rng.nextFloat(), u1 = i == 0 ? kOneMinusEpsilon : rng.nextFloat();
    const EnvironmentSample s = a.sample(u0, u1), t = b.sample(u0, u1);
    ASSERT_EQ(bitsOf(s.pdf), bitsOf(t.pdf)) << i;
    ASSERT_EQ(bitsOf(s.direction.x), bitsOf(t.direction.x));
    ASSERT_EQ(bitsOf(s.direction.y), bitsOf(t.direction.y));
    ASSERT_EQ(bitsOf(s.direction.z), bitsOf(t.direction.z));
    ASSERT_EQ(bitsOf(a.pdf(s.direction)), bitsOf(b.pdf(s.direction)));
  }
}

TEST(EnvironmentTable, RoundTripsAreBitIdentical) {
  const auto map = smoothMap(64, 32);
  for (EnvironmentSampling s :
       {EnvironmentSampling::Uniform, EnvironmentSampling::Adaptive, EnvironmentSampling::Compensated}) {
    SCOPED_TRACE(std::string(toString(s)));
    const EnvironmentLight built(map, withStrategy(s));
    const std::vector<std::byte> table = built.serializeTable();
    ASSERT_FALSE(table.empty());
    expectSameLight(built, EnvironmentLight(map, withStrategy(s), table));
  }
  // A constant map's compensation falls back to the plain adaptive table.
  const auto constant = constantMap(32, 16, 2.0f);
  const EnvironmentLight fellBack(constant, withStrategy(EnvironmentSampling::Compensated));
  ASSERT_TRUE(fellBack.compensationFellBack());
  expectSameLight(
      fellBack, EnvironmentLight(constant, withStrategy(EnvironmentSampling::Compensated), fellBack.serializeTable()));
}

TEST(EnvironmentTable, StrategiesWithoutACascadeSaveNothing) {
  const auto map = smoothMap(16, 8);
  for (EnvironmentSampling s : {EnvironmentSampling::Alias, EnvironmentSampling::Hierarchical}) {
    const EnvironmentLight light(map, withStrategy(s));
    EXPECT_TRUE(light.serializeTable().empty());
    expectSameLight(light, EnvironmentLight(map, withStrategy(s), std::span<const std::byte>{}));
  }
  const EnvironmentLight black(constantMap(16, 8, 0.0f), withStrategy(EnvironmentSampling::Adaptive));
  EXPECT_TRUE(black.serializeTable().empty());
}

std::string problemOf(const std::shared_ptr<const EnvironmentMap>& map, const EnvironmentLightOptions& options,
                      std::span<const std::byte> table) {
  try {
    EnvironmentLight light(map, options, table);
  } catch (const SerializationError& e) {
    return e.what();
  }
  return "";
}

TEST(EnvironmentTable, MismatchedOrCorruptTablesThrow) {
  const auto map = smoothMap(32, 16);
  const EnvironmentLightOptions adaptive = withStrategy(EnvironmentSampling::Adaptive);
  const std::vector<std::byte> table = EnvironmentLight(map, adaptive).serializeTable();
  EXPECT_NE(problemOf(smoothMap(16, 16), adaptive, table).find("another map size or other options"), std::string::npos);
  EXPECT_NE(problemOf(map, withStrategy(EnvironmentSampling::Uniform), table).find("other options"), std::string::npos);
  EnvironmentLightOptions finer = adaptive;
  finer.simplify.epsilon *= 0.5;
  EXPECT_NE(problemOf(map, finer, table).find("other options"), std::string::npos);
  EXPECT_NE(problemOf(map, withStrategy(EnvironmentSampling::Alias), table).find("has none"), std::string::npos);
  EXPECT_NE(problemOf(map, adaptive, std::span(table).first(table.size() / 2)).find("truncated"), std::string::npos);
  EXPECT_NE(problemOf(map, adaptive, {}).find("truncated"), std::string::npos);
}

TEST(EnvironmentTable, KeyFollowsPixelsAndEveryTableOption) {
  const auto map = smoothMap(32, 16);
  const EnvironmentLightOptions base;
  std::set<std::string> keys{EnvironmentLight::tableKey(*map, base).hex()};
  auto add = [&](const EnvironmentMap& m, const EnvironmentLightOptions& o) {
    EXPECT_TRUE(keys.insert(EnvironmentLight::tableKey(m, o).hex()).second);
  };
  for (EnvironmentSampling s : {EnvironmentSampling::Uniform, EnvironmentSampling::Alias,
                                EnvironmentSampling::Compensated, EnvironmentSampling::Hierarchical}) {
    add(*map, withStrategy(s));
  }
  EnvironmentLightOptions o = base;
  for (const SimplifyOptions& s : test_support::simplifyVariants(base.simplify)) {
    o.simplify = s;
    add(*map, o);
  }
  // The pixels: one channel of one pixel, and the same pixels in another shape.
  std::vector<float> rgb = map->rgb();
  rgb[3 * 77 + 2] = std::nextafter(rgb[3 * 77 + 2], 10.0f);
  add(EnvironmentMap(32, 16, rgb), base);
  add(EnvironmentMap(16, 32, map->rgb()), base);
  // Placement in the world does not change the table.
  o = base;
  o.scale = 3.0f;
  o.worldFromMap = Rotation::aboutY(0.5);
  EXPECT_EQ(EnvironmentLight::tableKey(*map, o), EnvironmentLight::tableKey(*map, base));
}

class EnvironmentTableCache : public apptest::TempDirTest {};

TEST_F(EnvironmentTableCache, CachedBuildsOnceThenLoads) {
  std::vector<std::string> warnings;
  TableCache cache(dir_ / "cache", [&](const std::string& w) { warnings.push_back(w); });
  const auto map = smoothMap(64, 32);
  const EnvironmentLightOptions options;
  const Cached<EnvironmentLight> first = EnvironmentLight::cached(cache, map, options, "sky");
  const Cached<EnvironmentLight> second = EnvironmentLight::cached(cache, map, options, "sky");
  EXPECT_FALSE(first.fromCache);
  EXPECT_TRUE(second.fromCache);
  expectSameLight(first.value, second.value);
  // Strategies whose table is not worth saving are built, and leave nothing in the cache.
  const std::size_t files = std::distance(std::filesystem::directory_iterator(dir_ / "cache"), {});
  for (EnvironmentSampling s : {EnvironmentSampling::Alias, EnvironmentSampling::Hierarchical})
    EXPECT_FALSE(EnvironmentLight::cached(cache, map, withStrategy(s), "sky").fromCache);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_ / "cache"), {}), files);
  EXPECT_TRUE(warnings.empty());
}

}  // namespace
