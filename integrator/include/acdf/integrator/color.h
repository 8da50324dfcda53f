#pragma once
// Linear RGB radiance and path throughput, in double: a pixel sums thousands of path
// contributions whose dynamic range (a sun next to a dark floor) float would round away.
// acdf::Rgb (float, no arithmetic) is what BRDFs and maps return; Color is what the renderer adds.

#include <algorithm>

#include "acdf/sampling/rgb.h"

namespace acdf {

struct Color {
  double r = 0, g = 0, b = 0;

  Color() = default;
  Color(double red, double green, double blue) : r(red), g(green), b(blue) {}
  explicit Color(double v) : r(v), g(v), b(v) {}
  explicit Color(const Rgb& c) : r(c.r), g(c.g), b(c.b) {}

  Color operator+(const Color& o) const { return {r + o.r, g + o.g, b + o.b}; }
  Color operator*(const Color& o) const { return {r * o.r, g * o.g, b * o.b}; }
  Color operator*(double s) const { return {r * s, g * s, b * s}; }
  Color& operator+=(const Color& o) { return *this = *this + o; }
  Color& operator*=(const Color& o) { return *this = *this * o; }
  Color& operator*=(double s) { return *this = *this * s; }

  bool isBlack() const { return r == 0 && g == 0 && b == 0; }
  double maxComponent() const { return std::max({r, g, b}); }
  // Rec. 709 weights, as Rgb::luminance.
  double luminance() const { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }
};

}  // namespace acdf
