#pragma once
// The radiance of an environment map: an equirectangular RGB image (lat_long.h gives each pixel's
// directions), cleaned up for use as a light.
//
// Real maps are dirty. Lossy compression (DWAB) leaves small negative values: each negative channel
// is clamped to 0 and the pixels affected are counted. NaN and Inf are rejected by the image
// reader (or replaced there, ImageReadOptions) and by the constructor. A map that is black
// everywhere is valid: a light that emits nothing.
//
// Radiance is looked up by nearest pixel — the pixel whose (θ, φ) cell holds the direction —
// which is exactly the function the sampling distributions (environment_light.h) tabulate.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "acdf/envmap/image_file.h"
#include "acdf/envmap/lat_long.h"
#include "acdf/sampling/rgb.h"

namespace acdf {

class EnvironmentMap {
 public:
  // rgb: height × width × 3 floats, row-major, row 0 = the top scanline (the zenith). Throws
  // std::invalid_argument for a zero size, a size mismatch or a NaN / Inf value (naming the pixel).
  EnvironmentMap(uint32_t width, uint32_t height, std::vector<float> rgb);

  // A gray image becomes R = G = B. Throws FileError (naming image's path) for NaN / Inf.
  static EnvironmentMap fromImage(const Image& image, const std::string& path);
  // readImage() + fromImage(). Throws FileError.
  static EnvironmentMap load(const std::string& path, const ImageReadOptions& options = {});

  uint32_t width() const { return mapping_.width(); }
  uint32_t height() const { return mapping_.height(); }
  const LatLongMapping& mapping() const { return mapping_; }

  Rgb radiance(PixelIndex p) const {
    const float* v = rgbOf(p);
    return {v[0], v[1], v[2]};
  }
  // Starts loading pixel p's radiance into the cache. The map is megabytes, so a sampled pixel is
  // usually a cache miss: a caller that knows the pixel before it needs the radiance lets its
  // other work (a direction, a pdf) hide the wait. Both ends: a pixel may straddle two lines.
  void prefetchRadiance(PixelIndex p) const {
    const float* v = rgbOf(p);
    __builtin_prefetch(v);
    __builtin_prefetch(v + 2);
  }
  // Nearest-pixel radiance in the map frame.
  Rgb radiance(const Vec3d& mapDirection) const { return radiance(mapping_.pixelOf(mapDirection)); }
  const std::vector<float>& rgb() const { return rgb_; }

  // Pixels that had at least one negative channel (now 0).
  std::size_t negativePixelsClamped() const { return negativePixelsClamped_; }
  // NaN / Inf channel values the reader replaced with 0 (load() with replaceNonFinite).
  std::size_t nonFiniteReplaced() const { return nonFiniteReplaced_; }
  bool isBlack() const { return black_; }
  // The chromaticities the file declared (the pixels were converted from them to Rec. 709 /
  // D65, image_file.h); none for a map made from pixels or a file that declares nothing.
  const std::optional<Chromaticities>& declaredChromaticities() const { return declaredChromaticities_; }

  // Per pixel, row-major: luminance × the pixel's solid angle ΔΩ (∝ luminance × sin θ at the
  // row's centre, since cos θa − cos θb = 2 sin(Δθ/2) sin θc): the power each pixel sends, the
  // function a light's sampling distribution tabulates. Sums and products in double.
  std::vector<float> pixelPower() const;
  // ∫ luminance dω over the sphere (Σ luminance × ΔΩ, double).
  double luminanceIntegral() const;

 private:
  const float* rgbOf(PixelIndex p) const { return &rgb_[3 * (std::size_t{p.row} * width() + p.column)]; }

  LatLongMapping mapping_;
  std::vector<float> rgb_;
  std::size_t negativePixelsClamped_ = 0;
  std::size_t nonFiniteReplaced_ = 0;
  std::optional<Chromaticities> declaredChromaticities_;
  bool black_ = true;
};

}  // namespace acdf
