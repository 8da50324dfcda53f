#pragma once
// The pixels of a render (the camera's crop window): per pixel the sum of the samples' radiance
// and of their squares, so the mean and its standard error are both at hand (the tests compare
// renders within error bars). The sums are in double: a pixel sums thousands of path
// contributions whose dynamic range (a sun next to a dark floor) float would round away.

#include <cstdint>
#include <string>
#include <vector>

#include "acdf/envmap/image_file.h"
#include "acdf/sampling/rgb.h"

namespace acdf {

class Film {
 public:
  Film(uint32_t width, uint32_t height) : width_(width), height_(height), pixels_(std::size_t{width} * height) {}

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }

  // The memory a width × height film takes while it renders and is written: its pixels and the
  // float image written from them.
  static double bytesFor(uint32_t width, uint32_t height);
  // This machine's physical memory, for refusing a film before allocating it.
  static double physicalMemoryBytes();

  // Not thread-safe for one pixel; distinct pixels may be added to concurrently.
  void add(uint32_t x, uint32_t y, const Rgb& sample) {
    Pixel& p = pixels_[std::size_t{y} * width_ + x];
    const float channels[3] = {sample.r, sample.g, sample.b};
    for (int c = 0; c < 3; ++c) {
      const double v = channels[c];
      p.sum[c] += v;
      p.sumSquares[c] += v * v;
    }
    ++p.samples;
  }

  Rgb mean(uint32_t x, uint32_t y) const;
  // Standard error of mean() per channel: √(sample variance / n); 0 below two samples.
  Rgb standardError(uint32_t x, uint32_t y) const;

  // Linear RGB means, row-major from the top.
  Image image() const;
  // Writes the linear float EXR and, unless pngPath is empty, the sRGB PNG preview, each to a
  // temporary file renamed into place. Throws FileError.
  void write(const std::string& exrPath, const std::string& pngPath) const;

 private:
  struct Pixel {
    double sum[3] = {0, 0, 0}, sumSquares[3] = {0, 0, 0};  // red, green, blue
    uint64_t samples = 0;
  };
  uint32_t width_, height_;
  std::vector<Pixel> pixels_;
};

}  // namespace acdf
