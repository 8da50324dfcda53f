#include "acdf/integrator/film.h"

#include <unistd.h>

#include <cmath>

namespace acdf {

double Film::bytesFor(uint32_t width, uint32_t height) {
  return static_cast<double>(width) * height * (sizeof(Pixel) + 3 * sizeof(float));
}

double Film::physicalMemoryBytes() {
  return static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
}

Rgb Film::mean(uint32_t x, uint32_t y) const {
  const Pixel& p = pixels_[std::size_t{y} * width_ + x];
  if (!p.samples) return {};
  const double scale = 1.0 / static_cast<double>(p.samples);
  return {static_cast<float>(p.sum[0] * scale), static_cast<float>(p.sum[1] * scale),
          static_cast<float>(p.sum[2] * scale)};
}

Rgb Film::standardError(uint32_t x, uint32_t y) const {
  const Pixel& p = pixels_[std::size_t{y} * width_ + x];
  if (p.samples < 2) return {};
  const double n = static_cast<double>(p.samples);
  auto se = [&](int c) {
    const double variance = std::fmax(0.0, (p.sumSquares[c] - p.sum[c] * p.sum[c] / n) / (n - 1.0));
    return static_cast<float>(std::sqrt(variance / n));
  };
  return {se(0), se(1), se(2)};
}

Image Film::image() const {
  Image image;
  image.width = width_;
  image.height = height_;
  image.channels = 3;
  image.pixels.reserve(pixels_.size() * 3);
  for (uint32_t y = 0; y < height_; ++y)
    for (uint32_t x = 0; x < width_; ++x) {
      const Rgb c = mean(x, y);
      image.pixels.insert(image.pixels.end(), {c.r, c.g, c.b});
    }
  return image;
}

void Film::write(const std::string& exrPath, const std::string& pngPath) const {
  const Image pixels = image();
  writeExr(exrPath, pixels);
  if (!pngPath.empty()) writeSrgbPng(pngPath, pixels);
}

}  // namespace acdf
