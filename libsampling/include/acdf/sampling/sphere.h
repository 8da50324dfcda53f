#pragma once
// Directions on the unit sphere: a small double 3-vector, spherical coordinates and the two
// standard warps every directional sampler is compared against (uniform sphere, cosine-weighted
// hemisphere). Frame: z up; θ is the polar angle from +z, φ the azimuth from +x towards +y.
//
// Double precision: directions feed angle conversions (acos/atan2 near the poles) and table
// lookups whose cell boundaries must be stable; a renderer may round the results to float.

#include <cmath>
#include <cstdint>
#include <numbers>

namespace acdf {

struct Vec3d {
  double x = 0, y = 0, z = 0;

  Vec3d operator+(const Vec3d& o) const { return {x + o.x, y + o.y, z + o.z}; }
  Vec3d operator-(const Vec3d& o) const { return {x - o.x, y - o.y, z - o.z}; }
  Vec3d operator-() const { return {-x, -y, -z}; }
  Vec3d operator*(double s) const { return {x * s, y * s, z * s}; }
  bool operator==(const Vec3d&) const = default;
};

inline double dot(const Vec3d& a, const Vec3d& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vec3d& v) { return std::sqrt(dot(v, v)); }
// v / |v|; v must not be zero.
inline Vec3d normalize(const Vec3d& v) { return v * (1.0 / length(v)); }

// The unit vector with polar angle theta and azimuth phi.
inline Vec3d sphericalDirection(double theta, double phi) {
  const double s = std::sin(theta);
  return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

struct SinCos {
  double sin = 0, cos = 1;
};

// sin and cos of 2π·turns, within 2e-16 of the exact values (2 ulp): a sampler's azimuth is a
// fraction of a turn, and knowing that makes the range reduction exact and cheap (about a third of
// libm's sincos). Whole quarter turns are split off exactly (turns − k/4 is representable for
// |turns| < 2^50), which leaves an angle x in [−π/4, π/4], where Taylor series to x^15 (sin) and
// x^16 (cos) are within 1e-16 of the functions.
inline SinCos sinCos2Pi(double turns) {
  constexpr double kRoundingShift = 0x1.8p52;  // adding and subtracting it rounds to an integer
  const double quarters = (4.0 * turns + kRoundingShift) - kRoundingShift;
  const double x = (turns - 0.25 * quarters) * (2.0 * std::numbers::pi);
  const double x2 = x * x;
  // Horner in x², coefficients ±1/n!.
  const double sinX =
      x + x * x2 *
              (-1.0 / 6 +
               x2 * (1.0 / 120 +
                     x2 * (-1.0 / 5040 +
                           x2 * (1.0 / 362880 +
                                 x2 * (-1.0 / 39916800 + x2 * (1.0 / 6227020800 + x2 * (-1.0 / 1307674368000)))))));
  const double cosX =
      1.0 + x2 * (-1.0 / 2 +
                  x2 * (1.0 / 24 +
                        x2 * (-1.0 / 720 +
                              x2 * (1.0 / 40320 +
                                    x2 * (-1.0 / 3628800 +
                                          x2 * (1.0 / 479001600 +
                                                x2 * (-1.0 / 87178291200 + x2 * (1.0 / 20922789888000))))))));
  // The angle is quadrant · π/2 + x: rotate (sin x, cos x) by that many quarter turns.
  const auto quadrant = static_cast<uint64_t>(static_cast<int64_t>(quarters));
  const bool swap = quadrant & 1u;
  const double s = swap ? cosX : sinX, c = swap ? sinX : cosX;
  return {quadrant & 2u ? -s : s, (quadrant + 1) & 2u ? -c : c};
}

// The unit vector with polar angle θ (given by its cosine and sine) and azimuth 2π·turns.
inline Vec3d directionAtTurns(double cosTheta, double sinTheta, double turns) {
  const SinCos phi = sinCos2Pi(turns);
  return {sinTheta * phi.cos, sinTheta * phi.sin, cosTheta};
}

// Polar angle in [0, π] of a (not necessarily unit) vector. atan2 rather than acos(z): the same
// angle, but accurate near the poles, where acos(1 − ε) loses half the digits.
inline double polarAngle(const Vec3d& v) { return std::atan2(std::hypot(v.x, v.y), v.z); }
// Azimuth in [0, 2π).
inline double azimuth(const Vec3d& v) {
  const double phi = std::atan2(v.y, v.x);
  return phi < 0.0 ? phi + 2.0 * std::numbers::pi : phi;
}

// A stand-in for atan2(y, x) taken in [0, 2π], by one division: strictly increasing in the angle
// α, 0 at α = 0 and 1, 2, 3 at π/2, π, 3π/2, towards 4 at 2π. Its slope in α is
// 1 / (|sin α| + |cos α|)², in [1/2, 1], so it never moves faster than α: a margin of m in it is a
// margin of at least m in the angle. Cell lookups compare it with precomputed cell edges instead
// of calling atan2. x, y not both zero (NaN otherwise).
inline double pseudoAngle(double y, double x) {
  const double t = x / (std::abs(x) + std::abs(y));
  return y >= 0.0 ? 1.0 - t : 3.0 + t;
}

// ωi = 2(ωo·n)n − ωo: the mirror image of ωo about the unit vector n.
inline Vec3d reflect(const Vec3d& wo, const Vec3d& n) { return n * (2.0 * dot(wo, n)) - wo; }

// Uniform on the sphere, density 1/(4π) per steradian. u0, u1 in [0, 1).
inline Vec3d sampleUniformSphere(double u0, double u1) {
  const double z = 1.0 - 2.0 * u0;
  return directionAtTurns(z, std::sqrt(std::fmax(0.0, 1.0 - z * z)), u1);
}
inline constexpr double kUniformSpherePdf = 1.0 / (4.0 * std::numbers::pi);

// Cosine-weighted on the upper (z > 0) hemisphere, density cosθ/π (Malley's method: uniform on
// the disk by the polar map, lifted to the hemisphere; u0 = 0 gives the pole). u0 → 1 approaches
// the horizon, where the density is 0: the radius is kept below 1 so every sample has cosθ > 0
// and a positive pdf.
inline Vec3d sampleCosineHemisphere(double u0, double u1) {
  const double r2 = std::fmin(u0, 1.0 - 0x1p-40);
  return directionAtTurns(std::sqrt(1.0 - r2), std::sqrt(r2), u1);
}
// cosθ/π above the horizon, 0 at and below it.
inline double cosineHemispherePdf(double cosTheta) { return cosTheta > 0.0 ? cosTheta * std::numbers::inv_pi : 0.0; }

}  // namespace acdf
