// The sample source: a pixel sample's values depend on the pixel, the sample index and the seed
// alone — not on the order pixel samples are asked for, on what was asked before, nor on which
// clone asks — and they lie in [0, 1).

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <tuple>
#include <vector>

#include "acdf/integrator/sampler.h"

namespace acdf {
namespace {

using PixelSample = std::tuple<uint32_t, uint32_t, uint32_t>;  // x, y, sample index

// The first values of a pixel sample, in the integrator's mix of calls: the pixel position, then
// per vertex a light 2D, a BSDF 2D and a roulette 1D.
std::vector<float> valuesOf(Sampler& sampler, const PixelSample& p, int vertices = 4) {
  const auto [x, y, s] = p;
  sampler.startPixelSample(x, y, s);
  const auto [px, py] = sampler.getPixel2D();
  std::vector<float> values{px, py};
  for (int v = 0; v < vertices; ++v) {
    for (int twice = 0; twice < 2; ++twice) {
      const auto [u0, u1] = sampler.get2D();
      values.push_back(u0);
      values.push_back(u1);
    }
    values.push_back(sampler.get1D());
  }
  return values;
}

std::vector<PixelSample> pixelSamples() {
  std::vector<PixelSample> all;
  for (uint32_t y : {0u, 1u, 37u})
    for (uint32_t x : {0u, 1u, 63u})
      for (uint32_t s : {0u, 1u, 2u, 1000u}) all.emplace_back(x, y, s);
  return all;
}

TEST(IndependentSampler, ValuesDependOnThePixelSampleAloneNotOnTheOrderAsked) {
  const IndependentSampler prototype(7, 64);
  std::map<PixelSample, std::vector<float>> inOrder;
  {
    const auto sampler = prototype.clone();
    for (const PixelSample& p : pixelSamples()) inOrder[p] = valuesOf(*sampler, p);
  }
  // Shuffled, from another clone that first consumed values of other pixel samples, and asking
  // some of them for fewer dimensions (a path that ended early).
  std::vector<PixelSample> shuffled = pixelSamples();
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(3));
  const auto other = prototype.clone();
  for (std::size_t i = 0; i < shuffled.size(); ++i) {
    (void)valuesOf(*other, {5, 5, static_cast<uint32_t>(i)}, static_cast<int>(i % 3));
    const std::vector<float> values = valuesOf(*other, shuffled[i]);
    EXPECT_EQ(values, inOrder.at(shuffled[i]));
  }
  // A sampler made afresh with the same seed and frame agrees too.
  IndependentSampler fresh(7, 64);
  EXPECT_EQ(valuesOf(fresh, {63, 37, 1000}), inOrder.at({63, 37, 1000}));
}

TEST(IndependentSampler, PixelsSamplesAndSeedsGetTheirOwnValues) {
  IndependentSampler sampler(7, 64), otherSeed(8, 64);
  std::map<std::vector<float>, PixelSample> seen;
  for (const PixelSample& p : pixelSamples()) {
    const std::vector<float> values = valuesOf(sampler, p);
    for (float v : values) {
      ASSERT_GE(v, 0.0f);
      ASSERT_LT(v, 1.0f);
    }
    EXPECT_TRUE(seen.emplace(values, p).second) << "two pixel samples with the same values";
    EXPECT_NE(valuesOf(otherSeed, p), values) << "the seed must matter";
  }
  // The frame's width numbers the pixels: the same (x, y) in a frame of another width is another
  // pixel.
  IndependentSampler narrow(7, 32);
  EXPECT_NE(valuesOf(narrow, {0, 1, 0}), valuesOf(sampler, {0, 1, 0}));
}

}  // namespace
}  // namespace acdf
