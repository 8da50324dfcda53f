#include "acdf/integrator/film.h"

#include <cmath>

namespace acdf {

Color Film::mean(uint32_t x, uint32_t y) const {
  const Pixel& p = pixels_[std::size_t{y} * width_ + x];
  return p.samples ? p.sum * (1.0 / static_cast<double>(p.samples)) : Color{};
}

Color Film::standardError(uint32_t x, uint32_t y) const {
  const Pixel& p = pixels_[std::size_t{y} * width_ + x];
  if (p.samples < 2) return {};
  const double n = static_cast<double>(p.samples);
  auto se = [n](double sum, double squares) {
    const double variance = std::fmax(0.0, (squares - sum * sum / n) / (n - 1.0));
    return std::sqrt(variance / n);
  };
  return {se(p.sum.r, p.sumSquares.r), se(p.sum.g, p.sumSquares.g), se(p.sum.b, p.sumSquares.b)};
}

Image Film::image() const {
  Image image;
  image.width = width_;
  image.height = height_;
  image.channels = 3;
  image.pixels.reserve(pixels_.size() * 3);
  for (uint32_t y = 0; y < height_; ++y)
    for (uint32_t x = 0; x < width_; ++x) {
      const Color c = mean(x, y);
      image.pixels.insert(image.pixels.end(),
                          {static_cast<float>(c.r), static_cast<float>(c.g), static_cast<float>(c.b)});
    }
  return image;
}

void Film::write(const std::string& exrPath, const std::string& pngPath) const {
  const Image pixels = image();
  writeExr(exrPath, pixels);
  if (!pngPath.empty()) writeSrgbPng(pngPath, pixels);
}

}  // namespace acdf
