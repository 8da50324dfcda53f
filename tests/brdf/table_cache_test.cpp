// Cached BRDF tables: a sampler made from buildCascade()'s table (directly or through a
// TableCache file) samples and evaluates bit for bit like one that built its own, a table of
// another grid or options is refused, and the key follows every MERL value, the interpolation,
// the model and every table option. Small tables (a synthetic glossy BRDF on coarse grids) keep
// it fast.

#include <gtest/gtest.h>

#include <unistd.h>
#include <bit>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/lambertian.h"
#include "acdf/brdf/merl.h"
#include "acdf/brdf/tabulated_brdf_sampler.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/table_cache.h"
#include "acdf/test_support/option_variants.h"

namespace {

using namespace acdf;
using Layout = TabulatedBrdfOptions::Layout;

// A glossy lobe around the specular direction over a diffuse floor, different per channel.
MerlBrdf glossy() {
  std::vector<double> rgb[3];
  for (int c = 0; c < 3; ++c) {
    rgb[c].resize(MerlBrdf::kCells);
    for (int h = 0; h < MerlBrdf::kThetaHalfCells; ++h)
      for (int d = 0; d < MerlBrdf::kThetaDiffCells; ++d)
        for (int p = 0; p < MerlBrdf::kPhiDiffCells; ++p)
          rgb[c][MerlBrdf::flatIndex(h, d, p)] = 20.0 * (c + 1) + 3000.0 * std::exp(-0.3 * h) * (1.0 + 0.01 * d);
  }
  return MerlBrdf(rgb[0], rgb[1], rgb[2]);
}

// Nearest-cell evaluation.
const std::shared_ptr<const MerlBrdf>& brdf() {
  static const auto b = std::make_shared<const MerlBrdf>(glossy());
  return b;
}

TabulatedBrdfOptions small(Layout layout, DimensionMethod method) {
  TabulatedBrdfOptions o;
  o.layout = layout;
  o.method = method;
  o.thetaOutCells = 6;
  o.phiOutCells = 4;
  o.thetaHalfCells = 32;
  o.phiHalfCells = 8;
  o.supersampling = 1;
  return o;
}

uint64_t bitsOf(double v) { return std::bit_cast<uint64_t>(v); }

void expectSameSampler(const TabulatedBrdfSampler& a, const TabulatedBrdfSampler& b) {
  ASSERT_EQ(a.table().serialize(), b.table().serialize());
  EXPECT_EQ(a.bytes(), b.bytes());
  Pcg32 rng(11);
  for (int i = 0; i < 2000; ++i) {
    const Vec3d wo = sphericalDirection(rng.nextDouble() * 1.5, rng.nextDouble() * 6.28);
    const float u0 = i == 0 ? 0.0f : rng.nextFloat(), u1 = i == 0 ? kOneMinusEpsilon : rng.nextFloat();
    const BrdfSample s = a.sample(wo, u0, u1), t = b.sample(wo, u0, u1);
    ASSERT_EQ(bitsOf(s.pdf), bitsOf(t.pdf)) << i;
    ASSERT_EQ(bitsOf(s.wi.x), bitsOf(t.wi.x));
    ASSERT_EQ(bitsOf(s.wi.y), bitsOf(t.wi.y));
    ASSERT_EQ(bitsOf(s.wi.z), bitsOf(t.wi.z));
    ASSERT_EQ(bitsOf(s.weight.r), bitsOf(t.weight.r));
  }
}

TEST(BrdfTable, SamplerFromASerializedTableIsBitIdentical) {
  for (Layout layout : {Layout::Full4D, Layout::Isotropic})
    for (DimensionMethod method : {DimensionMethod::Uniform, DimensionMethod::Adaptive}) {
      const TabulatedBrdfOptions o = small(layout, method);
      SCOPED_TRACE(o.name());
      const TabulatedBrdfSampler built(brdf(), o);
      const Cascade table = Cascade::deserialize(TabulatedBrdfSampler::buildCascade(*brdf(), o).serialize());
      expectSameSampler(built, TabulatedBrdfSampler(brdf(), o, table));
    }
}

TEST(BrdfTable, RefusesATableOfAnotherGridOrOptions) {
  const TabulatedBrdfOptions o = small(Layout::Full4D, DimensionMethod::Adaptive);
  const Cascade table = TabulatedBrdfSampler::buildCascade(*brdf(), o);
  TabulatedBrdfOptions finerGrid = o, otherEpsilon = o, uniform = o, isotropic = o;
  finerGrid.thetaHalfCells = 64;
  otherEpsilon.simplify.epsilon *= 2;
  uniform.method = DimensionMethod::Uniform;
  isotropic.layout = Layout::Isotropic;
  for (const TabulatedBrdfOptions& other : {finerGrid, otherEpsilon, uniform, isotropic}) {
    try {
      TabulatedBrdfSampler sampler(brdf(), other, table);
      ADD_FAILURE() << "accepted a table for " << o.name() << " as " << other.name();
    } catch (const SerializationError& e) {
      EXPECT_NE(std::string(e.what()).find("another grid or other options"), std::string::npos) << e.what();
    }
  }
  TabulatedBrdfOptions bad = o;
  bad.supersampling = 0;
  EXPECT_THROW(TabulatedBrdfSampler(brdf(), bad, table), std::invalid_argument);
}

TEST(BrdfTable, KeyFollowsEveryValueAndEveryTableOption) {
  const TabulatedBrdfOptions base = small(Layout::Full4D, DimensionMethod::Adaptive);
  std::set<std::string> keys{TabulatedBrdfSampler::tableKey(*brdf(), base).hex()};
  auto add = [&](const BrdfModel& b, const TabulatedBrdfOptions& o) {
    EXPECT_TRUE(keys.insert(TabulatedBrdfSampler::tableKey(b, o).hex()).second) << o.name();
  };
  add(brdf()->withInterpolation(MerlBrdf::Interpolation::Trilinear), base);
  // Other models, and each of their parameters.
  const AnalyticBrdf gold = AnalyticBrdf::preset("gold"), plastic = AnalyticBrdf::preset("red-plastic");
  add(gold, base);
  add(AnalyticBrdf::conductor(std::nextafter(gold.alpha(), 1.0), gold.f0()), base);
  add(AnalyticBrdf::conductor(gold.alpha(), {gold.f0()[0], gold.f0()[1], std::nextafter(gold.f0()[2], 1.0)}), base);
  add(plastic, base);
  add(AnalyticBrdf::coatedDiffuse(plastic.alpha(), plastic.albedo(), std::nextafter(plastic.ior(), 2.0)), base);
  add(AnalyticBrdf::coatedDiffuse(plastic.alpha(), {0.5, 0.05, std::nextafter(0.05, 1.0)}, plastic.ior()), base);
  add(LambertianBrdf({0.5f, 0.5f, 0.5f}), base);
  add(LambertianBrdf({0.5f, 0.5f, std::nextafter(0.5f, 1.0f)}), base);
  std::vector<TabulatedBrdfOptions> variants(7, base);
  variants[0].layout = Layout::Isotropic;
  variants[1].method = DimensionMethod::Uniform;
  variants[2].tolerance = ConditionalTolerance::Constant;
  variants[3].thetaOutCells = 7;
  variants[4].phiOutCells = 5;
  variants[5].thetaHalfCells = 33;
  variants[6].phiHalfCells = 10;
  for (const SimplifyOptions& s : test_support::simplifyVariants(base.simplify)) {
    variants.push_back(base);
    variants.back().simplify = s;
  }
  TabulatedBrdfOptions unmirrored = base, supersampled = base;
  unmirrored.mirror = false;
  supersampled.supersampling = 2;
  variants.push_back(unmirrored);
  variants.push_back(supersampled);
  for (const TabulatedBrdfOptions& v : variants) add(*brdf(), v);
  // One value of one channel.
  std::vector<double> rgb[3];
  for (int c = 0; c < 3; ++c) {
    const auto channel = brdf()->channel(c);
    rgb[c].assign(channel.begin(), channel.end());
  }
  rgb[2][123456] = std::nextafter(static_cast<float>(rgb[2][123456]), 1e9f);
  add(MerlBrdf(rgb[0], rgb[1], rgb[2]), base);
  // The defensive mixture weight only acts at sample time: the same table serves every weight.
  TabulatedBrdfOptions mixed = base;
  mixed.cosineWeight = 0.25;
  EXPECT_EQ(TabulatedBrdfSampler::tableKey(*brdf(), mixed), TabulatedBrdfSampler::tableKey(*brdf(), base));
  // Models of one table share its values: the same key (and so the cached table) for each.
  EXPECT_EQ(TabulatedBrdfSampler::tableKey(brdf()->withInterpolation(MerlBrdf::Interpolation::Nearest), base),
            TabulatedBrdfSampler::tableKey(*brdf(), base));
}

// The key hashes the values channel after channel, in file order, whatever the in-memory layout:
// tables cached under the planar layout's keys stay valid.
TEST(BrdfTable, KeyHashesTheChannelsInFileOrder) {
  ContentHash fromModel, fromChannels;
  EXPECT_EQ(brdf()->addToKey(fromModel), "interpolation=nearest");
  for (int c = 0; c < 3; ++c) {
    const auto channel = brdf()->channel(c);
    const std::vector<float> values(channel.begin(), channel.end());
    fromChannels.values(std::span<const float>(values));
  }
  EXPECT_EQ(fromModel.digest().hex(), fromChannels.digest().hex());
}

TEST(BrdfTable, ThroughATableCache) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("acdf-brdf-table-cache-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::vector<std::string> warnings;
  TableCache cache(dir, [&](const std::string& w) { warnings.push_back(w); });
  const TabulatedBrdfOptions o = small(Layout::Isotropic, DimensionMethod::Adaptive);
  auto get = [&] {
    return cache.getOrBuild(TabulatedBrdfSampler::tableKey(*brdf(), o), "BRDF table glossy",
                            [&] { return TabulatedBrdfSampler::buildCascade(*brdf(), o); });
  };
  Cached<Cascade> first = get(), second = get();
  EXPECT_FALSE(first.fromCache);
  EXPECT_TRUE(second.fromCache);
  expectSameSampler(TabulatedBrdfSampler(brdf(), o), TabulatedBrdfSampler(brdf(), o, std::move(second.value)));
  EXPECT_TRUE(warnings.empty());
  std::filesystem::remove_all(dir);
}

}  // namespace
