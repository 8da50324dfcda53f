// The guiding field without a renderer: a leaf's directional distribution is a proper density
// (chi-square against its own pdf, pdf(sample) equal to the returned pdf, integral 1, corner
// variates valid), it follows the energy it learned, a quadtree too deep for its cells' corners is
// rejected, and the spatial tree splits by record count and finds each point's leaf.

#include <cmath>
#include <numbers>
#include <span>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "acdf/integrator/guiding_field.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/sample.h"
#include "acdf/sampling/sphere_chi_square.h"
#include "acdf/test_support/chi_square_registry.h"

namespace acdf {
namespace {

// Records at `position` over the whole sphere: a dim uniform background and a bright cone of
// directions around `towards`, as a window seen from a room would give.
std::vector<GuidingRecord> windowRecords(const Vec3d& position, const Vec3d& towards, uint32_t count, uint64_t seed) {
  Pcg32 rng(seed);
  std::vector<GuidingRecord> records;
  for (uint32_t i = 0; i < count; ++i) {
    const double s = rng.nextFloat(), t = rng.nextFloat();
    const Vec3d d = equalAreaDirection(s, t);
    const double radiance = dot(d, towards) > 0.9 ? 50.0 : 0.2;
    // Uniform directions: density 1/4π.
    records.push_back(guidingRecord(position, {1, 0, 0}, d, radiance * 4 * std::numbers::pi));
  }
  return records;
}

// One distribution learned from `records`, with the storage that holds it.
struct OneDistribution {
  explicit OneDistribution(std::vector<GuidingRecord>& records)
      : all(std::vector<std::span<GuidingRecord>>{records}, GuidingFieldOptions{}), distribution(all[0]) {}
  DirectionalDistributions all;
  DirectionalDistribution distribution;
};

TEST(GuidingField, EqualAreaMapRoundTrips) {
  for (const Vec3d& d :
       {Vec3d{0, 0, 1}, Vec3d{0, 0, -1}, normalize(Vec3d{1, -2, 0.3}), normalize(Vec3d{-1, 0, -0.2})}) {
    const auto [s, t] = equalAreaSquare(d);
    EXPECT_GE(s, 0.0);
    EXPECT_LT(s, 1.0);
    EXPECT_GE(t, 0.0);
    EXPECT_LT(t, 1.0);
    const Vec3d back = equalAreaDirection(s, t);
    // At a pole s stops at the largest double below 1, √(2^-52) from it in x and y.
    EXPECT_NEAR(back.x, d.x, 1e-7);
    EXPECT_NEAR(back.y, d.y, 1e-7);
    EXPECT_NEAR(back.z, d.z, 1e-12);
  }
}

ACDF_CHI_SQUARE_TEST(GuidingField, DirectionalDistributionSamplesItsPdf, 1) {
  const Vec3d window = normalize(Vec3d{0.3, -0.5, 0.8});
  std::vector<GuidingRecord> records = windowRecords({0, 0, 0}, window, 20000, 7);
  const OneDistribution learned(records);
  const DirectionalDistribution& guide = learned.distribution;
  ASSERT_GT(guide.leaves(), 16u);

  SphereChiSquareOptions options;
  options.equalAreaRows = true;
  options.thetaBins = 64;
  options.phiBins = 64;
  options.subPoints = 16;
  options.alpha = test_support::chiSquareTestLevel();
  const SphereChiSquareReport report = sphereChiSquareTest(
      [&](float u0, float u1) {
        const auto s = guide.sample(u0, u1);
        return DirectionSample{s.direction, s.pdf};
      },
      [&](const Vec3d& d) { return guide.pdf(d); }, options);
  EXPECT_TRUE(report.passed()) << report.summary();
  EXPECT_NEAR(report.pdfIntegral, 1.0, 1e-3);
}

TEST(GuidingField, DirectionalDistributionFollowsTheEnergy) {
  const Vec3d window = normalize(Vec3d{0.3, -0.5, 0.8});
  std::vector<GuidingRecord> records = windowRecords({0, 0, 0}, window, 20000, 3);
  const OneDistribution learned(records);
  const DirectionalDistribution& guide = learned.distribution;
  // The cone holds 5 % of the sphere and 50 / (50 · 0.05 + 0.2 · 0.95) = 93 % of the energy.
  Pcg32 rng(11);
  int inCone = 0;
  constexpr int kSamples = 20000;
  for (int i = 0; i < kSamples; ++i) {
    const auto s = guide.sample(rng.nextFloat(), rng.nextFloat());
    inCone += dot(s.direction, window) > 0.9;
  }
  EXPECT_GT(inCone, 0.8 * kSamples);
  EXPECT_GT(guide.pdf(window), 10 * guide.pdf(-window));
}

TEST(GuidingField, CornerVariatesGiveValidSamples) {
  std::vector<GuidingRecord> records = windowRecords({0, 0, 0}, {0, 0, 1}, 5000, 5);
  const OneDistribution learned(records);
  const DirectionalDistribution& guide = learned.distribution;
  for (float u0 : {0.0f, kOneMinusEpsilon})
    for (float u1 : {0.0f, kOneMinusEpsilon}) {
      const auto s = guide.sample(u0, u1);
      EXPECT_TRUE(std::isfinite(s.pdf) && s.pdf > 0) << u0 << " " << u1;
      EXPECT_NEAR(length(s.direction), 1.0, 1e-12);
      EXPECT_DOUBLE_EQ(guide.pdf(s.direction), s.pdf);
    }
}

TEST(GuidingField, RejectsQuadtreesDeeperThanCellCornersResolve) {
  std::vector<GuidingRecord> records = windowRecords({0, 0, 0}, {0, 0, 1}, 100, 5);
  const GuidingFieldOptions options{.maxDirectionalDepth = DirectionalDistributions::kMaxDirectionalDepth + 1};
  EXPECT_THROW(GuidingField(records, options), std::invalid_argument);
}

TEST(GuidingField, SpatialTreeSplitsByRecordsAndFindsLeaves) {
  // Two rooms' worth of records, a window up in the one at x < 0 and one down in the one at x > 0.
  std::vector<GuidingRecord> records = windowRecords({-5, 0, 0}, {0, 0, 1}, 3000, 1);
  const std::vector<GuidingRecord> right = windowRecords({5, 0, 0}, {0, 0, -1}, 3000, 2);
  records.insert(records.end(), right.begin(), right.end());
  const GuidingField field(records, {.maxRecordsPerLeaf = 4000});
  EXPECT_EQ(field.spatialLeaves(), 2u);
  const DirectionalDistribution left = field.at({-5, 0, 0}, {1, 0, 0});
  const DirectionalDistribution rightLeaf = field.at({7, 1, 1}, {1, 0, 0});  // outside the records' box
  ASSERT_TRUE(left);
  ASSERT_TRUE(rightLeaf);
  EXPECT_GT(left.pdf({0, 0, 1}), 10 * left.pdf({0, 0, -1}));
  EXPECT_GT(rightLeaf.pdf({0, 0, -1}), 10 * rightLeaf.pdf({0, 0, 1}));
}

TEST(GuidingField, LeavesWithoutEnergyHaveNoDistribution) {
  std::vector<GuidingRecord> records = windowRecords({-5, 0, 0}, {0, 0, 1}, 3000, 1);
  for (uint32_t i = 0; i < 3000; ++i) records.push_back(guidingRecord({5, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.0));
  const GuidingField field(records, {.maxRecordsPerLeaf = 4000});
  EXPECT_TRUE(field.at({-5, 0, 0}, {1, 0, 0}));
  EXPECT_FALSE(field.at({5, 0, 0}, {1, 0, 0}));
}

}  // namespace
}  // namespace acdf
