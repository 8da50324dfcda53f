#pragma once
// The pixels of a render (the camera's crop window): per pixel the sum of the samples' radiance
// and of their squares, in double, so the mean and its standard error are both at hand (the
// tests compare renders within error bars).

#include <cstdint>
#include <string>
#include <vector>

#include "acdf/envmap/image_file.h"
#include "acdf/integrator/color.h"

namespace acdf {

class Film {
 public:
  Film(uint32_t width, uint32_t height) : width_(width), height_(height), pixels_(std::size_t{width} * height) {}

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }

  // Not thread-safe for one pixel; distinct pixels may be added to concurrently.
  void add(uint32_t x, uint32_t y, const Color& sample) {
    Pixel& p = pixels_[std::size_t{y} * width_ + x];
    p.sum += sample;
    p.sumSquares += sample * sample;
    ++p.samples;
  }

  Color mean(uint32_t x, uint32_t y) const;
  // Standard error of mean() per channel: √(sample variance / n); 0 below two samples.
  Color standardError(uint32_t x, uint32_t y) const;

  // Linear RGB means, row-major from the top.
  Image image() const;
  // Writes the linear float EXR and, unless pngPath is empty, the sRGB PNG preview, each to a
  // temporary file renamed into place. Throws ImageFileError.
  void write(const std::string& exrPath, const std::string& pngPath) const;

 private:
  struct Pixel {
    Color sum, sumSquares;
    uint64_t samples = 0;
  };
  uint32_t width_, height_;
  std::vector<Pixel> pixels_;
};

}  // namespace acdf
