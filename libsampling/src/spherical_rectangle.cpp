#include "acdf/sampling/spherical_rectangle.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace acdf {

namespace {
// The angle between the planes of two great circles given their unit normals n and m, at the
// vertex the two sides share: the inner angle of the spherical polygon there.
double innerAngle(const Vec3d& n, const Vec3d& m) { return std::acos(std::clamp(-dot(n, m), -1.0, 1.0)); }
}  // namespace

SphericalRectangle::SphericalRectangle(const Vec3d& origin, const Vec3d& corner, const Vec3d& edgeU,
                                       const Vec3d& edgeV)
    : origin_(origin), corner_(corner), edgeU_(edgeU), edgeV_(edgeV) {
  const double lengthU = length(edgeU), lengthV = length(edgeV);
  if (!(lengthU > 0) || !(lengthV > 0) || !std::isfinite(lengthU * lengthV))
    throw std::invalid_argument("spherical rectangle: its edges must be finite and non-zero");
  if (std::abs(dot(edgeU, edgeV)) > 1e-6 * lengthU * lengthV)
    throw std::invalid_argument("spherical rectangle: its edges must be perpendicular");
  x_ = edgeU * (1.0 / lengthU);
  y_ = edgeV * (1.0 / lengthV);
  z_ = cross(x_, y_);
  const Vec3d d = corner - origin;
  z0_ = dot(d, z_);
  if (z0_ > 0) {
    z0_ = -z0_;
    z_ = -z_;
  }
  x0_ = dot(d, x_);
  y0_ = dot(d, y_);
  x1_ = x0_ + lengthU;
  y1_ = y0_ + lengthV;
  if (!(z0_ < 0)) return;  // the origin lies in the rectangle's plane: it sees nothing

  // The unit normals of the four great circles through the rectangle's sides, in order around it:
  // the normalized cross products of the local corners (x0, y0, z0) × (x1, y0, z0) and so on
  // round the rectangle, each with one component zero in this frame.
  const Vec3d n0 = normalize({0, z0_, -y0_}), n1 = normalize({-z0_, 0, x1_});
  const Vec3d n2 = normalize({0, -z0_, y1_}), n3 = normalize({z0_, 0, -x0_});
  const double g0 = innerAngle(n0, n1), g1 = innerAngle(n1, n2), g2 = innerAngle(n2, n3), g3 = innerAngle(n3, n0);
  b0_ = n0.z;
  b1_ = n2.z;
  k_ = 2.0 * std::numbers::pi - g2 - g3;
  solidAngle_ = std::max(0.0, g0 + g1 - k_);
}

DirectionSample SphericalRectangle::sample(double u0, double u1) const {
  if (empty()) return {};
  // The slice x = xu whose part of the spherical rectangle, from x0 on, has area u0 · Ω.
  const double au = u0 * solidAngle_ + k_;
  const double fu = (std::cos(au) * b0_ - b1_) / std::sin(au);
  const double cu = std::clamp(std::copysign(1.0, fu) / std::sqrt(fu * fu + b0_ * b0_), -1.0, 1.0);
  double xu = -(cu * z0_) / std::sqrt(std::max(0.0, 1.0 - cu * cu));
  xu = xu >= x0_ ? std::min(xu, x1_) : x0_;  // NaN (sin au = 0 with a zero numerator) too
  // On that slice, the height uniform in sin(elevation): uniform in solid angle along it.
  // Plain square roots, not hypot: the constructor has squared these lengths already.
  const double dist2 = xu * xu + z0_ * z0_, dist = std::sqrt(dist2);
  const double h0 = y0_ / std::sqrt(dist2 + y0_ * y0_), h1 = y1_ / std::sqrt(dist2 + y1_ * y1_);
  const double hv = h0 + u1 * (h1 - h0), hv2 = hv * hv;
  const double yv = hv2 < 1.0 - 1e-12 ? std::clamp(hv * dist / std::sqrt(1.0 - hv2), y0_, y1_) : y1_;
  return {normalize(x_ * xu + y_ * yv + z_ * z0_), 1.0 / solidAngle_};
}

bool SphericalRectangle::passesThrough(const Vec3d& origin, const Vec3d& corner, const Vec3d& edgeU,
                                       const Vec3d& edgeV, const Vec3d& w) {
  const Vec3d normal = cross(edgeU, edgeV);
  const double towards = dot(w, normal), height = dot(corner - origin, normal);
  // The plane ahead along w: the two dot products of the same sign, neither zero.
  if (!(towards * height > 0)) return false;
  const Vec3d hit = origin + w * (height / towards) - corner;
  const double s = dot(hit, edgeU) / dot(edgeU, edgeU), t = dot(hit, edgeV) / dot(edgeV, edgeV);
  constexpr double kSpare = 1e-9;
  return s >= -kSpare && s <= 1.0 + kSpare && t >= -kSpare && t <= 1.0 + kSpare;
}

double SphericalRectangle::solidAngleOf(const Vec3d& origin, const Vec3d& corner, const Vec3d& edgeU,
                                        const Vec3d& edgeV) {
  // The triangles (a, b, c) and (a, c, d) of the corners a, b = a + edgeU, c = b + edgeV,
  // d = a + edgeV. Both triple products reduce to a · (edgeU × edgeV), computed so: no
  // cancellation between nearly parallel corner vectors.
  const Vec3d a = corner - origin, b = a + edgeU, c = b + edgeV, d = a + edgeV;
  const double volume = std::abs(dot(a, cross(edgeU, edgeV)));
  if (!(volume > 0)) return 0.0;
  const double la = length(a), lb = length(b), lc = length(c), ld = length(d), ac = dot(a, c);
  // Each triangle's Ω/2 is the argument of denominator + i·volume, divided by the product of its
  // corners' lengths (which keeps the argument) to unit scale; Ω/2 of the rectangle, below π, is
  // the argument of their product: one atan2.
  const double scaleB = 1.0 / (la * lb * lc), scaleD = 1.0 / (la * lc * ld);
  const double reB = (la * lb * lc + dot(a, b) * lc + ac * lb + dot(b, c) * la) * scaleB, imB = volume * scaleB;
  const double reD = (la * lc * ld + ac * ld + dot(a, d) * lc + dot(c, d) * la) * scaleD, imD = volume * scaleD;
  return 2.0 * std::atan2(reB * imD + imB * reD, reB * reD - imB * imD);
}

}  // namespace acdf
