#pragma once
// The equirectangular (latitude-longitude) layout of an environment map: which direction each
// pixel covers. The convention is OpenEXR's LatLong environment map (ImfEnvmap.h), so files tagged
// "LatLong Environment" appear as their authors intended, unmirrored:
//
//   map frame: +Y up. θ ∈ [0, π] is the polar angle from +Y, φ ∈ [0, 2π) the azimuth;
//     ω(θ, φ) = (sinθ sinφ, cosθ, −sinθ cosφ)
//   so the left edge of the image (φ = 0) looks along −Z, a quarter of the way in along +X, the
//   centre column along +Z and three quarters along −X. In OpenEXR's terms φ = π − longitude and
//   θ = π/2 − latitude. Seen from inside the sphere the image is not mirrored: a camera looking
//   along +Z (the centre column) with +Y up has the image's left half (towards +X) on its left.
//
//   pixel (row r, column c) of a W × H map covers, exactly:
//     θ ∈ [π r / H, π (r + 1) / H)   (row 0 = the top scanline, around the zenith)
//     φ ∈ [2π c / W, 2π (c + 1) / W)
//   and the solid angle ΔΩ_r = (cos θ_r − cos θ_{r+1}) · 2π / W, the same for every pixel of a row.
//
// Pixel centres. OpenEXR spreads the pixel *centres* from pole to pole and seam to seam: centre
// (r, c) sits at θ = π r / (H − 1), φ = 2π c / (W − 1), so the first and last rows are points on the
// poles and the first and last columns both lie on the seam. acdf instead gives every pixel an
// equal share of the sphere's (θ, φ) rectangle (centre θ = π (r + ½) / H, φ = 2π (c + ½) / W), which
// a light needs: the pixels tile the sphere exactly, each with a positive solid angle, and a
// sample's pixel is the cell it falls in. The two agree on the equator and the centre column; the
// offset grows linearly to half a pixel at the poles and at the seam (θ: π / (2H) at rows 0 and
// H − 1; φ: π / W at columns 0 and W − 1), so every acdf pixel centre lies within half a pixel of
// OpenEXR's centre for the same pixel (tests/envmap/openexr_latlong_test.cpp checks it against
// Imf::LatLongMap).
//
// In the z-up frame of acdf/sampling/sphere.h (θ from +z, φ from +x towards +y) the same (θ, φ)
// is the direction toZUp(ω) = (−ω.z, ω.x, ω.y). That change of frame is orthogonal but a
// reflection (determinant −1), because φ turns clockwise seen from +Y here and counter-clockwise
// seen from +z there: it preserves angles and solid angles, so sphere.h's tools (the chi-square
// test's (θ, φ) bins) apply after toZUp(); a handedness-dependent quantity (a cross product)
// would not carry over.
//
// Inside a pixel, directionInPixel() spreads positions uniformly in solid angle (uniform in cos θ
// and in φ): a density that is constant per pixel in (θ, φ) space would instead vary as 1/sin θ in
// solid angle within the pixel, and a light whose radiance is constant per pixel (nearest lookup)
// could then never be sampled with zero variance.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "acdf/sampling/sphere.h"
#include "acdf/sampling/threshold_cells.h"

namespace acdf {

struct PixelIndex {
  uint32_t row = 0, column = 0;
  bool operator==(const PixelIndex&) const = default;
};

class LatLongMapping {
 public:
  // width, height >= 1.
  LatLongMapping(uint32_t width, uint32_t height);

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }

  static Vec3d direction(double theta, double phi) {
    const double s = std::sin(theta);
    return {s * std::sin(phi), std::cos(theta), -s * std::cos(phi)};
  }
  // θ of a (not necessarily unit) direction, by atan2: accurate near the poles, unlike acos(y).
  static double theta(const Vec3d& w) { return std::atan2(std::hypot(w.x, w.z), w.y); }
  // φ in [0, 2π); 0 on the Y axis.
  static double phi(const Vec3d& w) {
    const double p = std::atan2(w.x, -w.z);
    return p < 0.0 ? p + 2.0 * std::numbers::pi : p;
  }
  // The same direction in sphere.h's z-up frame, where its angles are this mapping's θ and φ
  // (a reflection, see above).
  static Vec3d toZUp(const Vec3d& w) { return {-w.z, w.x, w.y}; }
  static Vec3d fromZUp(const Vec3d& v) { return {v.y, v.z, -v.x}; }

  // The pixel whose (θ, φ) cell holds w; w must not be zero or NaN. Exactly pixelByAngles(w), found
  // without atan2 unless w lies within 1e-9 of a pixel's edge (the seam φ = 0 = 2π and the
  // axes aside).
  PixelIndex pixelOf(const Vec3d& w) const;
  // The same by the definition: theta(w) and phi(w) scaled to pixels, floored, clamped.
  PixelIndex pixelByAngles(const Vec3d& w) const {
    const double row = theta(w) * (height_ * std::numbers::inv_pi);
    const double column = phi(w) * (width_ * 0.5 * std::numbers::inv_pi);
    return {std::min(static_cast<uint32_t>(row), height_ - 1), std::min(static_cast<uint32_t>(column), width_ - 1)};
  }

  // The direction at fractions (s, t) ∈ [0, 1]² of pixel p, uniform in solid angle: cos θ moves
  // linearly from the top edge (s = 0) to the bottom edge, φ from the left (t = 0) to the right.
  // Fractions are kept kPixelMargin inside the pixel so that pixelOf() of the result is p despite
  // rounding (a 1e-6 shift of the density at pixel edges, far below any test's resolution).
  Vec3d directionInPixel(PixelIndex p, double s, double t) const {
    s = std::clamp(s, kPixelMargin, 1.0 - kPixelMargin);
    t = std::clamp(t, kPixelMargin, 1.0 - kPixelMargin);
    const double cosTheta = cosEdge_[p.row] + s * (cosEdge_[p.row + 1] - cosEdge_[p.row]);
    // (1 − c)(1 + c) rather than 1 − c²: no cancellation near the poles.
    const double sinTheta = std::sqrt(std::max(0.0, (1.0 - cosTheta) * (1.0 + cosTheta)));
    const SinCos phi = sinCos2Pi((p.column + t) / width_);
    return {sinTheta * phi.sin, cosTheta, -sinTheta * phi.cos};
  }

  // ΔΩ of every pixel of `row`.
  double pixelSolidAngle(uint32_t row) const {
    return (cosEdge_[row] - cosEdge_[row + 1]) * (2.0 * std::numbers::pi / width_);
  }

  static constexpr double kPixelMargin = 1e-6;

 private:
  uint32_t width_, height_;
  std::vector<double> cosEdge_;  // cos θ at the top edge of each row, and at the bottom (−1)
  // pixelOf()'s rows and columns by pseudo-angles of θ (in [0, 2]) and φ (in [0, 4]), stepping
  // up at the pseudo-angles of the edges θ = π k / H and φ = 2π k / W.
  ThresholdCells rowCells_, columnCells_;
  uint32_t equatorRow_ = 0;       // the row of θ = π/2
  uint32_t axisColumns_[4] = {};  // the columns of φ = 0, π/2, π, 3π/2
};

}  // namespace acdf
