#pragma once
// Directions towards a rectangle, uniform in the solid angle it subtends from a point: the
// area-preserving parametrization of spherical rectangles (Ureña, Fajardo & King 2013). What a
// portal — a window or a door the environment is seen through — needs first: every direction it
// returns passes through the rectangle, and its density is 1 / Ω, constant, where a sample drawn
// on the rectangle's area and converted to solid angle would have a density that grows without
// bound towards grazing corners.
//
// In the rectangle's frame centred on the origin (x along edgeU, y along edgeV, z the normal
// towards the origin's side), the rectangle is [x0, x1] × [y0, y1] in the plane z = z0 < 0. The
// spherical rectangle's area is Ω = g0 + g1 + g2 + g3 − 2π, the sum of its four inner angles
// minus 2π. A first variate picks the azimuthal slice through the rectangle with its share of
// Ω (the area of the spherical quadrilateral up to it grows linearly in the slice's x, solved in
// closed form), the second picks the height on that slice uniformly in the sine of the
// elevation, which is uniform in solid angle along the slice.
//
// Exact in double but for one place: a slice whose height is nearly the whole hemisphere (a
// rectangle almost containing the zenith of its plane) rounds its hv² to 1; the point is then
// clamped to the slice's far end. The chi-square tests below measure it where it matters.

#include "acdf/sampling/sphere.h"
#include "acdf/sampling/sphere_chi_square.h"

namespace acdf {

class SphericalRectangle {
 public:
  // The rectangle {corner + s·edgeU + t·edgeV : s, t ∈ [0, 1]} seen from `origin`. edgeU and
  // edgeV must be perpendicular and non-zero (a portal's loader checks and names them; here
  // std::invalid_argument). An origin in the rectangle's plane sees nothing: empty().
  SphericalRectangle(const Vec3d& origin, const Vec3d& corner, const Vec3d& edgeU, const Vec3d& edgeV);

  // Ω, the solid angle of the rectangle from the origin, in steradians: (0, 2π).
  double solidAngle() const { return solidAngle_; }
  bool empty() const { return !(solidAngle_ > 0); }

  // A unit direction from the origin through the rectangle, uniform in solid angle, for u0, u1
  // in [0, 1] (either end included); pdf 1 / Ω. empty(): pdf 0, no direction.
  DirectionSample sample(double u0, double u1) const;
  // 1 / Ω for a direction whose ray from the origin meets the rectangle (passesThrough), 0
  // otherwise; w need not be unit length.
  double pdf(const Vec3d& w) const {
    return !empty() && passesThrough(origin_, corner_, edgeU_, edgeV_, w) ? 1.0 / solidAngle_ : 0.0;
  }
  // Whether the ray from `origin` along w meets the rectangle, its edges included with 1e-9 of an
  // edge's length to spare (a sample on an edge stays inside after its normalisation's rounding).
  // No solid angle is computed: what a caller that knows Ω already needs for a pdf.
  static bool passesThrough(const Vec3d& origin, const Vec3d& corner, const Vec3d& edgeU, const Vec3d& edgeV,
                            const Vec3d& w);
  // Ω alone, without the sampling construction: the rectangle as two triangles, each
  // tan(Ω/2) = |a · (b × c)| / (|a||b||c| + (a · b)|c| + (a · c)|b| + (b · c)|a|) for its corners
  // a, b, c seen from the origin (Van Oosterom & Strackee 1983), the two halves added as the
  // arguments of a complex product: one atan2. Same edge requirements, unchecked; 0 for an origin
  // in the rectangle's plane. A third of solidAngle()'s time and more precise: its sum of four
  // angles minus 2π cancels as Ω shrinks (relative errors against long double, over Ω from 1e-7 to
  // 2π: here 1e-15 typical, 5e-12 at worst; there 1e-14 typical above 0.1 sr, 1e-3 below 1e-6).
  static double solidAngleOf(const Vec3d& origin, const Vec3d& corner, const Vec3d& edgeU, const Vec3d& edgeV);

 private:
  Vec3d origin_, corner_, edgeU_, edgeV_;
  Vec3d x_, y_, z_;  // the frame: z the plane's normal towards the origin's side
  double x0_ = 0, x1_ = 0, y0_ = 0, y1_ = 0, z0_ = 0;
  double b0_ = 0, b1_ = 0, k_ = 0;
  double solidAngle_ = 0;
};

}  // namespace acdf
