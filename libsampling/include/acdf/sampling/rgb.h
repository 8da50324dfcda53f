#pragma once
// Linear RGB (Rec. 709 primaries), the one colour type of the tree: BRDF values and weights,
// environment radiance, path throughput. Float: measurements are good to a few percent, and float
// is what renderers carry per path (pbrt-v4's SampledSpectrum, Mitsuba's Color3f); sums over
// many paths are kept in double where they are made (Film's pixels, the estimators).

#include <algorithm>

namespace acdf {

struct Rgb {
  float r = 0, g = 0, b = 0;

  bool operator==(const Rgb&) const = default;

  Rgb operator+(const Rgb& o) const { return {r + o.r, g + o.g, b + o.b}; }
  Rgb operator*(const Rgb& o) const { return {r * o.r, g * o.g, b * o.b}; }
  Rgb operator*(float s) const { return {r * s, g * s, b * s}; }
  Rgb& operator+=(const Rgb& o) { return *this = *this + o; }
  Rgb& operator*=(const Rgb& o) { return *this = *this * o; }
  Rgb& operator*=(float s) { return *this = *this * s; }

  bool isBlack() const { return r == 0 && g == 0 && b == 0; }
  float maxComponent() const { return std::max({r, g, b}); }
  // Rec. 709 / sRGB luminance, the same weights the cdf-stats tool uses for images. MERL data and
  // our environment maps are in (approximately) linear sRGB primaries.
  float luminance() const { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
};

}  // namespace acdf
