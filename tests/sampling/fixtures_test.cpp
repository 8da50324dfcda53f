// The fixtures themselves: deterministic, the documented shapes, and a sun that is what the
// quality tests and benchmarks assume it is.

#include "acdf/fixtures/fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace fx = acdf::fixtures;

namespace {

constexpr double kPi = std::numbers::pi;

TEST(Fixtures, AreDeterministic) {
  const uint32_t dims[] = {16, 8, 12};
  EXPECT_EQ(fx::smooth(dims), fx::smooth(dims));
  EXPECT_EQ(fx::peakedSun(dims), fx::peakedSun(dims));
  EXPECT_EQ(fx::zerosWithIslands(dims), fx::zerosWithIslands(dims));
  EXPECT_EQ(fx::checkerboard(dims), fx::checkerboard(dims));
  EXPECT_EQ(fx::random(dims, 7), fx::random(dims, 7));
  EXPECT_NE(fx::random(dims, 7), fx::random(dims, 8));
  EXPECT_EQ(fx::sunAndSky(64, 32), fx::sunAndSky(64, 32));
}

TEST(Fixtures, RejectBadDims) {
  EXPECT_THROW(fx::smooth(std::vector<uint32_t>{}), std::invalid_argument);
  EXPECT_THROW(fx::smooth(std::vector<uint32_t>{2, 2, 2, 2, 2}), std::invalid_argument);
  EXPECT_THROW(fx::random(std::vector<uint32_t>{4, 0}, 1), std::invalid_argument);
  EXPECT_THROW(fx::sunAndSky(0, 4), std::invalid_argument);
  EXPECT_EQ(fx::cellCount(std::vector<uint32_t>{3, 4, 5, 6}), 360u);
}

TEST(Fixtures, SizesAndRanges) {
  for (const std::vector<uint32_t>& dims :
       {std::vector<uint32_t>{1000}, {64, 32}, {16, 8, 12}, {8, 4, 32, 16}, {1}, {1, 1, 1}}) {
    const std::size_t n = fx::cellCount(dims);
    const auto s = fx::smooth(dims);
    ASSERT_EQ(s.size(), n);
    EXPECT_GE(*std::min_element(s.begin(), s.end()), 0.1f);
    EXPECT_LE(*std::max_element(s.begin(), s.end()), 1.6f);
    const auto r = fx::random(dims, 3);
    ASSERT_EQ(r.size(), n);
    for (float v : r) ASSERT_TRUE(v >= 0.0f && v < 1.0f);
    const auto c = fx::checkerboard(dims);
    ASSERT_EQ(c.size(), n);
    EXPECT_EQ(c[0], 1.0f);
    for (float v : c) ASSERT_TRUE(v == 0.0f || v == 1.0f);
    const auto z = fx::zerosWithIslands(dims);
    ASSERT_EQ(z.size(), n);
    EXPECT_GT(std::accumulate(z.begin(), z.end(), 0.0), 0.0);
  }
}

TEST(Fixtures, PeakedSunHasOnePeak) {
  const uint32_t dims[] = {64, 32};
  const auto s = fx::smooth(dims);
  const auto p = fx::peakedSun(dims);
  const std::size_t peak = fx::peakedSunCell(dims);
  EXPECT_EQ(peak, std::size_t(23) * 32 + 11);  // floor(0.37·64), floor(0.37·32)
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (i == peak)
      EXPECT_NEAR(p[i] / s[i], 1e6, 1.0);
    else
      ASSERT_EQ(p[i], s[i]) << i;
  }
}

TEST(Fixtures, IslandsAreMostlyZeroAndRectangular) {
  const uint32_t dims[] = {16, 8, 12};
  const auto z = fx::zerosWithIslands(dims);
  const auto zeros = std::count(z.begin(), z.end(), 0.0f);
  EXPECT_GT(double(zeros) / double(z.size()), 0.9);
  // Island 1 covers cells [1, 4) on axis 0, [0, 2) on axis 1, [1, 3) on axis 2.
  EXPECT_EQ(z[(1 * 8 + 0) * 12 + 1], 1.0f);
  EXPECT_EQ(z[(3 * 8 + 1) * 12 + 2], 1.0f);
  EXPECT_EQ(z[(4 * 8 + 1) * 12 + 2], 0.0f);
  const std::vector<uint32_t> oneD = {1000};
  const auto z1 = fx::zerosWithIslands(oneD);
  EXPECT_EQ(std::count(z1.begin(), z1.end(), 50.0f), 10);  // [850, 860)
  EXPECT_EQ(std::count(z1.begin(), z1.end(), 5.0f), 50);   // [550, 600)
  EXPECT_EQ(std::count(z1.begin(), z1.end(), 1.0f), 150);  // [100, 250)
}

TEST(Fixtures, CheckerboardBlocks) {
  const uint32_t dims[] = {64, 32};
  const auto c = fx::checkerboard(dims, 1.0f, 100.0f);
  // Blocks of 8 × 4 cells.
  EXPECT_EQ(c[0], 100.0f);
  EXPECT_EQ(c[7 * 32 + 3], 100.0f);
  EXPECT_EQ(c[8 * 32 + 0], 1.0f);
  EXPECT_EQ(c[0 * 32 + 4], 1.0f);
  EXPECT_EQ(c[8 * 32 + 4], 100.0f);
}

TEST(Fixtures, SunAndSkyShape) {
  constexpr uint32_t W = 1024, H = 512;
  const auto v = fx::sunAndSky(W, H);
  ASSERT_EQ(v.size(), std::size_t(W) * H);
  const double sun = fx::sunRadiance();
  EXPECT_NEAR(sun / fx::skyAverageLuminance(), 1e5, 1e-6);
  // The sky average is 0.3 + 0.7/3 plus the glow's share.
  EXPECT_GT(fx::skyAverageLuminance(), 0.3 + 0.7 / 3.0);
  EXPECT_LT(fx::skyAverageLuminance(), 0.3 + 0.7 / 3.0 + 0.2);

  // The brightest cell holds the sun's centre (θ = 65°, φ = 1.2).
  const std::size_t brightest = std::max_element(v.begin(), v.end()) - v.begin();
  const double theta = (brightest / W + 0.5) * kPi / H, phi = (brightest % W + 0.5) * 2 * kPi / W;
  EXPECT_NEAR(theta, fx::kSunTheta, 2 * kPi / H);
  EXPECT_NEAR(phi, fx::kSunPhi, 2 * 2 * kPi / W);

  // At least one cell is fully covered by the disk: value = sunRadiance · sinθ.
  int full = 0, partial = 0;
  double sunMass = 0, total = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    total += v[i];
    const double sinT = std::sin((i / W + 0.5) * kPi / H);
    const double coverage = v[i] / (sun * sinT);
    if (coverage > 0.999)
      ++full;
    else if (coverage > 0.01)
      ++partial;
    if (coverage > 0.01) sunMass += v[i];
  }
  EXPECT_GE(full, 1);
  EXPECT_GE(partial, 4);  // partial coverage of the disk's rim
  std::cout << "sunAndSky 1024x512: full sun cells " << full << ", partial " << partial << ", sun share of the total "
            << sunMass / total << "\n";
  EXPECT_GT(sunMass / total, 0.5);  // the sun dominates the map's energy

  // Sky brighter toward the horizon (away from the sun), ground = 0.05·sinθ.
  const auto cell = [&](double th, double ph) {
    return v[std::size_t(th / kPi * H) * W + std::size_t(ph / (2 * kPi) * W)];
  };
  const double awayPhi = fx::kSunPhi + kPi;
  EXPECT_LT(cell(0.3, awayPhi) / std::sin(0.3), cell(1.4, awayPhi) / std::sin(1.4));
  const std::size_t groundRow = 400;
  const double groundSin = std::sin((groundRow + 0.5) * kPi / H);
  EXPECT_NEAR(v[groundRow * W + 10], 0.05 * groundSin, 1e-7);
  // The zenith row is weighted by sinθ ≈ 0.
  EXPECT_LT(v[5], 0.01f);
}

}  // namespace
