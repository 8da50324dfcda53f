#include "acdf/integrator/render_error.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace acdf {

namespace {

// A pixel whose relative difference (√ of its relMSE term) reaches this is drawn full red.
constexpr double kFullRedDifference = 0.5;

}  // namespace

RenderError renderError(const Image& image, const Image& reference) {
  double relSum = 0, sqSum = 0;
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    const double r = reference.pixels[i], d = double(image.pixels[i]) - r;
    relSum += d * d / (r * r + kRelMseOffset);
    sqSum += d * d;
  }
  const double n = static_cast<double>(image.pixels.size());
  return {relSum / n, std::sqrt(sqSum / n)};
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
