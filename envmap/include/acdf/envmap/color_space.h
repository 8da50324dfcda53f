#pragma once
// RGB colour spaces given by chromaticities, and the conversion of a file's RGB to the one space
// acdf computes in: linear Rec. 709 primaries with a D65 white (sRGB's, and Mitsuba 3's and
// pbrt-v4's default).
//
// An OpenEXR file may declare its primaries and white point (the `chromaticities` attribute; maps
// saved from Photoshop often carry a D50 white). Such pixels are converted as OpenEXR defines the
// attribute and as Mitsuba 3 reads it: RGB → CIE XYZ by the file's primaries, scaled so that RGB
// (1, 1, 1) is the file's white at luminance Y = 1; then XYZ → Rec. 709 RGB. There is no chromatic
// adaptation (no Bradford or von Kries step): the XYZ of each pixel is kept, so a D50 white
// becomes a slightly warm Rec. 709 colour of the same luminance, exactly what Mitsuba's `envmap`
// sees in the same file.

#include <array>
#include <optional>
#include <string>

namespace acdf {

// CIE 1931 xy chromaticities of the red, green and blue primaries and of the white point.
struct Chromaticities {
  using Xy = std::array<double, 2>;
  Xy red, green, blue, white;
};

// ITU-R BT.709 primaries, D65 white: what OpenEXR assumes when a file declares nothing.
inline constexpr Chromaticities kRec709{{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}, {0.3127, 0.3290}};

// Row-major 3 × 3: out[i] = Σ_j m[i][j] in[j].
using ColorMatrix = std::array<std::array<double, 3>, 3>;

// Why c does not define an RGB space, or nothing: a non-finite coordinate, a white with y <= 0
// (no luminance to scale by), primaries that do not span XYZ (collinear in xy) or a white on a
// side of their triangle. Primaries may have y <= 0 (XYZ's own, ACES AP0's blue).
std::optional<std::string> chromaticitiesProblem(const Chromaticities& c);

// RGB of c → XYZ, RGB (1, 1, 1) ↦ the white point at Y = 1. Throws std::invalid_argument with
// chromaticitiesProblem()'s text.
ColorMatrix xyzFromRgb(const Chromaticities& c);

// RGB of `from` → RGB of `to`, through XYZ without chromatic adaptation (see above). Throws
// std::invalid_argument with chromaticitiesProblem()'s text.
ColorMatrix rgbFromRgb(const Chromaticities& to, const Chromaticities& from);
// RGB of c → linear Rec. 709 RGB: rgbFromRgb(kRec709, c).
ColorMatrix rec709FromRgb(const Chromaticities& c);

// The same space as far as a float file can tell: every coordinate within 1e-4 of `b`'s.
bool sameChromaticities(const Chromaticities& a, const Chromaticities& b);

// "red (0.64, 0.33), green (...), blue (...), white (...)", for messages and reports.
std::string toString(const Chromaticities& c);

}  // namespace acdf
