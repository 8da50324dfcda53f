// The error figures of `acdf bench-error`: relMSE and RMSE by hand, the trimmed relMSE dropping
// exactly the worst 0.1% of pixels, and the mean, standard error and delta-method efficiency
// error over seeds against values worked out by hand.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "acdf/experiments/render_error.h"

namespace acdf {
namespace {

Image grey(uint32_t width, uint32_t height, float value) {
  Image image;
  image.width = width;
  image.height = height;
  image.channels = 3;
  image.pixels.assign(std::size_t(width) * height * 3, value);
  return image;
}

TEST(RenderError, RelMseAndRmseByHand) {
  const Image reference = grey(4, 2, 1.0f);
  Image image = grey(4, 2, 1.5f);
  const RenderError e = renderError(image, reference);
  EXPECT_NEAR(e.relMse, 0.25 / 1.01, 1e-12);
  EXPECT_NEAR(e.rmse, 0.5, 1e-12);
  EXPECT_NEAR(e.relMseTrimmed, e.relMse, 1e-12) << "8 pixels: none discarded";
}

TEST(RenderError, TrimmedRelMseDropsTheWorstTenthOfAPercentOfPixels) {
  // 2000 pixels: the 2 worst are discarded. Two fireflies in one channel each and a third,
  // smaller one that is kept.
  const Image reference = grey(100, 20, 1.0f);
  Image image = grey(100, 20, 1.1f);
  image.pixels[3 * 17 + 1] = 1000.0f;
  image.pixels[3 * 1234] = 500.0f;
  image.pixels[3 * 1500 + 2] = 3.0f;
  const double d = double(1.1f) - 1, base = d * d / 1.01;  // every other channel's term
  const RenderError e = renderError(image, reference);
  const double third = (2 * base + 4.0 / 1.01) / 3;  // the pixel with the smaller firefly
  EXPECT_NEAR(e.relMseTrimmed, (1997 * base + third) / 1998, 1e-6 * base);
  EXPECT_GT(e.relMse, 1000 * e.relMseTrimmed) << "the fireflies dominate relMSE";

  // 1999 pixels: ⌊1.999⌋ = 1 discarded, the second firefly counts.
  const Image reference2 = grey(1999, 1, 1.0f);
  Image image2 = grey(1999, 1, 1.1f);
  image2.pixels[3 * 17 + 1] = 1000.0f;
  image2.pixels[3 * 1234] = 500.0f;
  const double second = (2 * base + 499.0 * 499.0 / 1.01) / 3;
  EXPECT_NEAR(renderError(image2, reference2).relMseTrimmed, (1997 * base + second) / 1998, 1e-6 * second / 1998);
}

TEST(RenderError, MeanAndStandardErrorOverSeeds) {
  const std::vector<double> values = {1, 2, 3, 4};
  const MeanAndError m = meanAndError(values);
  EXPECT_DOUBLE_EQ(m.mean, 2.5);
  EXPECT_NEAR(m.standardError, std::sqrt(5.0 / 3.0) / 2, 1e-15);  // s = √(5/3), K = 4
  const std::vector<double> one = {7};
  EXPECT_EQ(meanAndError(one).mean, 7);
  EXPECT_EQ(meanAndError(one).standardError, 0) << "one seed cannot estimate its error";
}

TEST(RenderError, EfficiencyAndItsDeltaMethodError) {
  // relMSE 1, 2, 3 and seconds 2, 2, 5: r = 2, t = 3, se_r = 1/√3, se_t = 1, cov = 1.5.
  std::vector<SeedRender> seeds(3);
  const double relMse[] = {1, 2, 3}, seconds[] = {2, 2, 5};
  for (int i = 0; i < 3; ++i) {
    seeds[i].error.relMse = seeds[i].error.relMseTrimmed = relMse[i];
    seeds[i].error.rmse = 1;
    seeds[i].seconds = seconds[i];
  }
  const SeedAggregate a = aggregateSeeds(seeds);
  EXPECT_DOUBLE_EQ(a.relMse.mean, 2);
  EXPECT_DOUBLE_EQ(a.seconds.mean, 3);
  EXPECT_EQ(a.rmse.standardError, 0);
  EXPECT_DOUBLE_EQ(a.efficiency.mean, 1.0 / 6);
  // (σ_E / E)² = (1/3) / 4 + 1 / 9 + 2 · 1.5 / (3 · 2 · 3).
  EXPECT_NEAR(a.efficiency.standardError, std::sqrt(1.0 / 12 + 1.0 / 9 + 1.0 / 6) / 6, 1e-15);

  // A constant render time: the error is relMSE's relative error.
  for (SeedRender& s : seeds) s.seconds = 4;
  const SeedAggregate c = aggregateSeeds(seeds);
  EXPECT_NEAR(c.efficiency.standardError / c.efficiency.mean, c.relMse.standardError / c.relMse.mean, 1e-15);
  EXPECT_THROW(aggregateSeeds(std::span<const SeedRender>()), std::invalid_argument);
}

TEST(RenderError, TimeToReachATargetIsInterpolatedLogLog) {
  // relMSE 0.08, 0.04, 0.01 at 1, 2, 4 s (slope −1 then −2); target 0.02 lies between 2 s and 4 s
  // at w = ln(0.02 / 0.04) / ln(0.01 / 0.04) = 1/2: t* = 2 · 2^(1/2).
  const std::vector<ErrorAtTime> curve = {{1, {0.08, 0.008}}, {2, {0.04, 0.004}}, {4, {0.01, 0.002}}};
  const TimeToTarget t = timeToReach(curve, 0.02);
  EXPECT_FALSE(t.extrapolated);
  EXPECT_NEAR(t.seconds, 2 * std::sqrt(2.0), 1e-12);
  // δ = 0.1 and 0.2: σ_t / t* = √((0.5 · 0.1)² + (0.5 · 0.2)²) / 2.
  EXPECT_NEAR(t.standardError / t.seconds, std::hypot(0.05, 0.1) / 2, 1e-12);
  // On a measured point: that point's time.
  EXPECT_NEAR(timeToReach(curve, 0.04).seconds, 2, 1e-12);
  EXPECT_NEAR(timeToReach(curve, 0.08).seconds, 1, 1e-12);
}

TEST(RenderError, TimeToReachATargetOutsideTheCurveIsExtrapolatedByOneOverTime) {
  const std::vector<ErrorAtTime> curve = {{1, {0.08, 0.008}}, {2, {0.04, 0.004}}, {4, {0.01, 0.002}}};
  const TimeToTarget slower = timeToReach(curve, 0.001);  // not reached: from the last point
  EXPECT_TRUE(slower.extrapolated);
  EXPECT_NEAR(slower.seconds, 40, 1e-12);
  EXPECT_NEAR(slower.standardError, 40 * 0.2, 1e-12);
  const TimeToTarget faster = timeToReach(curve, 0.16);  // reached before the first point
  EXPECT_TRUE(faster.extrapolated);
  EXPECT_NEAR(faster.seconds, 0.5, 1e-12);
  // A curve that rises (noise) never crosses downward: extrapolated from its first point.
  const std::vector<ErrorAtTime> rising = {{1, {0.01, 0}}, {2, {0.03, 0}}};
  EXPECT_NEAR(timeToReach(rising, 0.02).seconds, 0.5, 1e-12);
  // Unusable points are ignored; none left gives NaN.
  const std::vector<ErrorAtTime> zero = {{1, {0, 0}}, {0, {0.1, 0}}};
  EXPECT_TRUE(std::isnan(timeToReach(zero, 0.02).seconds));
  EXPECT_TRUE(std::isnan(timeToReach(curve, 0).seconds));
}

}  // namespace
}  // namespace acdf
