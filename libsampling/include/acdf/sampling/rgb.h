#pragma once
// An RGB triple, the one colour type that measured BRDFs and environment maps share. Float:
// measurements are good to a few percent, and a renderer consumes floats.

namespace acdf {

struct Rgb {
  float r = 0, g = 0, b = 0;

  bool operator==(const Rgb&) const = default;

  // Rec. 709 / sRGB luminance, the same weights the cdf-stats tool uses for images. MERL data and
  // our environment maps are in (approximately) linear sRGB primaries.
  float luminance() const { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
};

}  // namespace acdf
