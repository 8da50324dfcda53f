#include "acdf/envmap/color_space.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace acdf {

namespace {

double determinant(const ColorMatrix& m) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

ColorMatrix inverse(const ColorMatrix& m) {
  const double d = determinant(m);
  ColorMatrix r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      // The cofactor of m[j][i] (the adjugate's transpose), by cyclic indices.
      const int a = (j + 1) % 3, b = (j + 2) % 3, c = (i + 1) % 3, e = (i + 2) % 3;
      r[i][j] = (m[a][c] * m[b][e] - m[a][e] * m[b][c]) / d;
    }
  return r;
}

ColorMatrix product(const ColorMatrix& a, const ColorMatrix& b) {
  ColorMatrix r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) r[i][j] += a[i][k] * b[k][j];
  return r;
}

// The primaries' chromaticities as columns (x, y, 1 - x - y): each primary's XYZ up to a scale.
// (Not divided by y: a primary may have y <= 0, as XYZ's own and ACES AP0's blue do.)
ColorMatrix primaryColumns(const Chromaticities& c) {
  return {{{c.red[0], c.green[0], c.blue[0]},
           {c.red[1], c.green[1], c.blue[1]},
           {1 - c.red[0] - c.red[1], 1 - c.green[0] - c.green[1], 1 - c.blue[0] - c.blue[1]}}};
}

// The scale of each primary column that makes their sum the white point's XYZ at Y = 1.
std::array<double, 3> primaryScales(const Chromaticities& c) {
  const ColorMatrix pInverse = inverse(primaryColumns(c));
  const std::array<double, 3> w{c.white[0] / c.white[1], 1.0, (1 - c.white[0] - c.white[1]) / c.white[1]};
  std::array<double, 3> s{};
  for (int j = 0; j < 3; ++j) s[j] = pInverse[j][0] * w[0] + pInverse[j][1] * w[1] + pInverse[j][2] * w[2];
  return s;
}

}  // namespace

std::optional<std::string> chromaticitiesProblem(const Chromaticities& c) {
  for (const auto& [name, xy] : {std::pair{"red", c.red}, {"green", c.green}, {"blue", c.blue}, {"white", c.white}})
    if (!std::isfinite(xy[0]) || !std::isfinite(xy[1])) return fmt::format("the {} chromaticity is not finite", name);
  if (c.white[1] <= 0) return fmt::format("the white chromaticity has y = {} (must be > 0)", c.white[1]);
  if (std::abs(determinant(primaryColumns(c))) <= 1e-6)  // Rec. 709's is 0.22, XYZ's 1
    return "the red, green and blue chromaticities are collinear (they do not span a colour space)";
  for (double scale : primaryScales(c))
    if (!(std::abs(scale) > 1e-9) || !std::isfinite(scale))
      return "the white chromaticity lies on a side of the primaries' triangle (a primary would have no weight)";
  return std::nullopt;
}

ColorMatrix xyzFromRgb(const Chromaticities& c) {
  if (const auto problem = chromaticitiesProblem(c)) throw std::invalid_argument(*problem);
  ColorMatrix m = primaryColumns(c);
  const auto s = primaryScales(c);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m[i][j] *= s[j];
  return m;
}

ColorMatrix rgbFromRgb(const Chromaticities& to, const Chromaticities& from) {
  return product(inverse(xyzFromRgb(to)), xyzFromRgb(from));
}

ColorMatrix rec709FromRgb(const Chromaticities& c) { return rgbFromRgb(kRec709, c); }

bool sameChromaticities(const Chromaticities& a, const Chromaticities& b) {
  const auto near = [](const Chromaticities::Xy& p, const Chromaticities::Xy& q) {
    return std::abs(p[0] - q[0]) <= 1e-4 && std::abs(p[1] - q[1]) <= 1e-4;
  };
  return near(a.red, b.red) && near(a.green, b.green) && near(a.blue, b.blue) && near(a.white, b.white);
}

std::string toString(const Chromaticities& c) {
  return fmt::format("red ({:.4f}, {:.4f}), green ({:.4f}, {:.4f}), blue ({:.4f}, {:.4f}), white ({:.4f}, {:.4f})",
                     c.red[0], c.red[1], c.green[0], c.green[1], c.blue[0], c.blue[1], c.white[0], c.white[1]);
}

}  // namespace acdf
