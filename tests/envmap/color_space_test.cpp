// Colour spaces from chromaticities (color_space.h): the matrices against published worked
// examples, the conversion without chromatic adaptation Mitsuba 3 makes, and chromaticities that
// define no RGB space.

#include "acdf/envmap/color_space.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

namespace acdf {
namespace {

// Adobe RGB (1998): Rec. 709's red and blue, a greener green, the same D65 white.
constexpr Chromaticities kAdobeRgb{{0.64, 0.33}, {0.21, 0.71}, {0.15, 0.06}, {0.3127, 0.3290}};
// ProPhoto (ROMM) RGB with its D50 white, as Photoshop writes it.
constexpr Chromaticities kProPhoto{{0.7347, 0.2653}, {0.1596, 0.8404}, {0.0366, 0.0001}, {0.3457, 0.3585}};

void expectMatrixNear(const ColorMatrix& got, const ColorMatrix& want, double tolerance) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(got[i][j], want[i][j], tolerance) << "[" << i << "][" << j << "]";
}

std::array<double, 3> transform(const ColorMatrix& m, std::array<double, 3> v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

TEST(ColorSpace, Rec709ToXyzIsSrgbsMatrix) {
  // IEC 61966-2-1's RGB -> XYZ (its Y row is the luminance weights 0.2126, 0.7152, 0.0722).
  expectMatrixNear(xyzFromRgb(kRec709),
                   {{{0.4124, 0.3576, 0.1805}, {0.2126, 0.7152, 0.0722}, {0.0193, 0.1192, 0.9505}}}, 1e-4);
}

TEST(ColorSpace, Rec709IsLeftAsItIs) {
  expectMatrixNear(rec709FromRgb(kRec709), {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, 1e-12);
  EXPECT_TRUE(sameChromaticities(kRec709, {{0.64f, 0.33f}, {0.30f, 0.60f}, {0.15f, 0.06f}, {0.3127f, 0.3290f}}));
  EXPECT_FALSE(sameChromaticities(kRec709, kAdobeRgb));
}

TEST(ColorSpace, AdobeRgbToRec709IsThePublishedMatrix) {
  // The worked example of Adobe RGB (1998) -> linear sRGB (same white): R' = 1.39836 R - 0.39836 G,
  // G' = G, B' = -0.04293 G + 1.04293 B.
  expectMatrixNear(rec709FromRgb(kAdobeRgb), {{{1.39836, -0.39836, 0}, {0, 1, 0}, {0, -0.04293, 1.04293}}}, 1e-5);
}

TEST(ColorSpace, D50WhiteKeepsItsXyzWithoutChromaticAdaptation) {
  // ProPhoto's white (1, 1, 1) is D50 at Y = 1; no adaptation to D65 is made, so it stays D50's
  // XYZ: a warm Rec. 709 colour of luminance 1 (what Mitsuba 3's envmap reads from the same file:
  // 1.17646, 0.975617, 0.721779).
  const auto white = transform(rec709FromRgb(kProPhoto), {1, 1, 1});
  EXPECT_NEAR(white[0], 1.176464, 1e-5);
  EXPECT_NEAR(white[1], 0.975617, 1e-5);
  EXPECT_NEAR(white[2], 0.721779, 1e-5);
  const auto xyz = transform(xyzFromRgb(kRec709), white);
  EXPECT_NEAR(xyz[1], 1.0, 1e-12);
  EXPECT_NEAR(xyz[0] / (xyz[0] + xyz[1] + xyz[2]), 0.3457, 1e-12);
  EXPECT_NEAR(xyz[1] / (xyz[0] + xyz[1] + xyz[2]), 0.3585, 1e-12);
}

TEST(ColorSpace, XyzDeclaredAsPrimariesIsXyz) {
  // Mitsuba writes XYZ images declaring these "primaries" (two with y = 0): their RGB is XYZ.
  const Chromaticities xyz{{1, 0}, {0, 1}, {0, 0}, {1.0 / 3, 1.0 / 3}};
  expectMatrixNear(xyzFromRgb(xyz), {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, 1e-12);
  // ACES 2065-1 (AP0): a blue primary below y = 0.
  EXPECT_FALSE(chromaticitiesProblem({{0.7347, 0.2653}, {0.0, 1.0}, {0.0001, -0.0770}, {0.32168, 0.33767}}));
}

TEST(ColorSpace, ChromaticitiesThatDefineNoSpaceAreNamed) {
  Chromaticities collinear = kRec709;
  collinear.green = {0.395, 0.195};  // on the line from red to blue
  ASSERT_TRUE(chromaticitiesProblem(collinear));
  EXPECT_NE(chromaticitiesProblem(collinear)->find("collinear"), std::string::npos);
  Chromaticities dark = kRec709;
  dark.white = {0.3, 0.0};
  EXPECT_NE(chromaticitiesProblem(dark)->find("white chromaticity has y = 0"), std::string::npos);
  Chromaticities onASide = kRec709;
  onASide.white = {0.47, 0.465};  // the midpoint of red and green
  EXPECT_NE(chromaticitiesProblem(onASide)->find("side of the primaries"), std::string::npos);
  Chromaticities nan = kRec709;
  nan.blue[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(chromaticitiesProblem(nan)->find("blue chromaticity is not finite"), std::string::npos);
  EXPECT_THROW((void)rec709FromRgb(collinear), std::invalid_argument);
  EXPECT_FALSE(chromaticitiesProblem(kProPhoto));
}

}  // namespace
}  // namespace acdf
