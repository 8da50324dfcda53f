#include "acdf/experiments/render_error.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <stdexcept>
#include <vector>

namespace acdf {

namespace {

// A pixel whose relative difference (√ of its relMSE term) reaches this is drawn full red.
constexpr double kFullRedDifference = 0.5;

}  // namespace

RenderError renderError(const Image& image, const Image& reference) {
  double relSum = 0, sqSum = 0;
  const std::size_t channels = std::max<uint32_t>(image.channels, 1);
  std::vector<double> pixelTerms(image.pixels.size() / channels);
  for (std::size_t p = 0; p < pixelTerms.size(); ++p) {
    double pixelSum = 0;
    for (std::size_t c = 0; c < channels; ++c) {
      const std::size_t i = p * channels + c;
      const double r = reference.pixels[i], d = double(image.pixels[i]) - r;
      pixelSum += d * d / (r * r + kRelMseOffset);
      sqSum += d * d;
    }
    relSum += pixelSum;
    pixelTerms[p] = pixelSum / static_cast<double>(channels);
  }
  const double n = static_cast<double>(image.pixels.size());
  // The trimmed mean: the largest terms moved to the back, the front summed.
  const std::size_t discarded = static_cast<std::size_t>(kTrimmedFraction * static_cast<double>(pixelTerms.size()));
  const std::size_t kept = pixelTerms.size() - discarded;
  std::nth_element(pixelTerms.begin(), pixelTerms.begin() + static_cast<std::ptrdiff_t>(kept), pixelTerms.end());
  double trimmedSum = 0;
  for (std::size_t p = 0; p < kept; ++p) trimmedSum += pixelTerms[p];
  return {relSum / n, std::sqrt(sqSum / n), kept > 0 ? trimmedSum / static_cast<double>(kept) : 0.0};
}

MeanAndError meanAndError(std::span<const double> values) {
  if (values.empty()) return {};
  const double k = static_cast<double>(values.size());
  double sum = 0;
  for (double v : values) sum += v;
  const double mean = sum / k;
  if (values.size() < 2) return {mean, 0};
  double sq = 0;
  for (double v : values) sq += (v - mean) * (v - mean);
  return {mean, std::sqrt(sq / (k - 1) / k)};
}

SeedAggregate aggregateSeeds(std::span<const SeedRender> seeds) {
  if (seeds.empty()) throw std::invalid_argument("aggregateSeeds: no seeds");
  const auto over = [&](const std::function<double(const SeedRender&)>& field) {
    std::vector<double> values;
    for (const SeedRender& s : seeds) values.push_back(field(s));
    return meanAndError(values);
  };
  SeedAggregate a;
  a.relMse = over([](const SeedRender& s) { return s.error.relMse; });
  a.relMseTrimmed = over([](const SeedRender& s) { return s.error.relMseTrimmed; });
  a.rmse = over([](const SeedRender& s) { return s.error.rmse; });
  a.seconds = over([](const SeedRender& s) { return s.seconds; });
  const double r = a.relMse.mean, t = a.seconds.mean;
  if (!(r > 0) || !(t > 0)) return a;  // a perfect or instant render has no finite efficiency
  a.efficiency.mean = 1 / (r * t);
  const double k = static_cast<double>(seeds.size());
  double cov = 0;
  if (seeds.size() > 1) {
    for (const SeedRender& s : seeds) cov += (s.error.relMse - r) * (s.seconds - t);
    cov /= k - 1;
  }
  const double rel2 = (a.relMse.standardError / r) * (a.relMse.standardError / r) +
                      (a.seconds.standardError / t) * (a.seconds.standardError / t) + 2 * cov / (k * r * t);
  a.efficiency.standardError = a.efficiency.mean * std::sqrt(std::max(rel2, 0.0));
  return a;
}

TimeToTarget timeToReach(std::span<const ErrorAtTime> points, double target) {
  std::vector<ErrorAtTime> usable;
  for (const ErrorAtTime& p : points)
    if (p.seconds > 0 && p.relMse.mean > 0 && std::isfinite(p.seconds) && std::isfinite(p.relMse.mean))
      usable.push_back(p);
  if (usable.empty() || !(target > 0)) return {std::nan(""), std::nan(""), false};
  const auto delta = [](const ErrorAtTime& p) { return p.relMse.standardError / p.relMse.mean; };
  for (std::size_t i = 0; i + 1 < usable.size(); ++i) {
    const ErrorAtTime &a = usable[i], &b = usable[i + 1];
    if (!(a.relMse.mean >= target && b.relMse.mean <= target && b.relMse.mean < a.relMse.mean && b.seconds > a.seconds))
      continue;
    const double x1 = std::log(a.seconds), x2 = std::log(b.seconds);
    const double y1 = std::log(a.relMse.mean), y2 = std::log(b.relMse.mean);
    const double w = (std::log(target) - y1) / (y2 - y1), slope = (y2 - y1) / (x2 - x1);
    const double seconds = std::exp(x1 + w * (x2 - x1));
    const double relative = std::hypot((1 - w) * delta(a), w * delta(b)) / std::abs(slope);
    return {seconds, seconds * relative, false};
  }
  const ErrorAtTime& from = usable.front().relMse.mean <= target ? usable.front() : usable.back();
  const double seconds = from.seconds * from.relMse.mean / target;
  return {seconds, seconds * delta(from), true};
}

Image differenceImage(const Image& a, const Image& b, const Image& reference) {
  Image out;
  out.width = reference.width;
  out.height = reference.height;
  out.channels = 3;
  out.pixels.resize(reference.pixels.size());
  for (std::size_t p = 0; p < reference.pixels.size(); p += 3) {
    double term = 0, luminance = 0;
    constexpr double kWeights[3] = {0.2126, 0.7152, 0.0722};
    for (int c = 0; c < 3; ++c) {
      const double r = reference.pixels[p + c], d = double(a.pixels[p + c]) - b.pixels[p + c];
      term += d * d / (r * r + kRelMseOffset) / 3;
      luminance += kWeights[c] * r;
    }
    const float t = static_cast<float>(std::min(1.0, std::sqrt(term) / kFullRedDifference));
    const float grey = static_cast<float>(0.2 * std::clamp(luminance, 0.0, 1.0));
    out.pixels[p] = grey + t * (1 - grey);
    out.pixels[p + 1] = out.pixels[p + 2] = grey * (1 - t);
  }
  return out;
}

}  // namespace acdf
