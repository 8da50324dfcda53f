#include "acdf/brdf/coordinates.h"

#include <cmath>

namespace acdf {

namespace {

// Azimuth in (−π, π], MERL's range. (polarAngle() is atan2-based rather than MERL's acos(z): the
// same angle, accurate near the pole.)
double signedAzimuth(const Vec3d& v) { return std::atan2(v.y, v.x); }

// Rotation by an angle with cosine c and sine s about z, then about y (right-handed,
// counter-clockwise seen from +axis). These are MERL's rotate_vector (Rodrigues' formula) with
// the axis fixed, written out.
Vec3d rotateZ(const Vec3d& v, double c, double s) { return {c * v.x - s * v.y, s * v.x + c * v.y, v.z}; }
Vec3d rotateY(const Vec3d& v, double c, double s) { return {c * v.x + s * v.z, v.y, c * v.z - s * v.x}; }
Vec3d rotateZ(const Vec3d& v, double angle) { return rotateZ(v, std::cos(angle), std::sin(angle)); }
Vec3d rotateY(const Vec3d& v, double angle) { return rotateY(v, std::cos(angle), std::sin(angle)); }

}  // namespace

HalfVectorFrame::HalfVectorFrame(double thetaHalf, double phiHalf)
    : thetaHalf_(thetaHalf),
      cosPhi_(std::cos(-phiHalf)),
      sinPhi_(std::sin(-phiHalf)),
      cosTheta_(std::cos(-thetaHalf)),
      sinTheta_(std::sin(-thetaHalf)) {}

Vec3d HalfVectorFrame::difference(const Vec3d& wi) const {
  return rotateY(rotateZ(wi, cosPhi_, sinPhi_), cosTheta_, sinTheta_);
}

void HalfVectorFrame::diffAngles(const Vec3d& wi, double& thetaDiff, double& phiDiff) const {
  const Vec3d d = difference(wi);
  thetaDiff = polarAngle(d);
  phiDiff = signedAzimuth(d);
}

HalfDiffAngles toHalfDiff(const Vec3d& wo, const Vec3d& wi) { return toHalfDiff(wo, wi, true); }

HalfDiffVectors halfDiffVectors(const Vec3d& wo, const Vec3d& wi) {
  // h need not be normalised: its angles are atan2's, which are scale-free, and the rotation's
  // cosines and sines are ratios of its components, cos φh = x/ρ, sin φh = y/ρ, cos θh = z/|h|,
  // sin θh = ρ/|h|, without evaluating the angles' trigonometric functions. On the normal (ρ = 0)
  // φh is 0; the degenerate ωi = −ωo has no half vector at all: take the normal, so the result
  // stays finite.
  // ρ as a plain square root, not hypot: the sum has no components near overflow or underflow,
  // and hypot's last-bit rounding costs three times as much.
  HalfDiffVectors v;
  v.half = wi + wo;
  v.rho = std::sqrt(v.half.x * v.half.x + v.half.y * v.half.y);
  v.length = std::sqrt(v.rho * v.rho + v.half.z * v.half.z);
  double cosPhi = 1, sinPhi = 0, cosTheta = 1, sinTheta = 0;
  if (v.rho > 0) cosPhi = v.half.x / v.rho, sinPhi = v.half.y / v.rho;
  if (v.length > 0) cosTheta = v.half.z / v.length, sinTheta = v.rho / v.length;
  // d = Ry(−θh) · Rz(−φh) · ωi.
  v.diff = rotateY(rotateZ(wi, cosPhi, -sinPhi), cosTheta, -sinTheta);
  // With either direction on the normal (θo = 0 or θi = 0), ωi, ωo and h lie in one plane with
  // the normal, so d has no binormal component and φd is 0 or π exactly, MERL's φd cell 0 (as
  // BRDFRead.cpp gives in exact arithmetic). The rotation leaves a rounding residue of either
  // sign there instead, which picked cell 0 or 179 (12% apart on nickel) for the same directions.
  if ((wo.x == 0.0 && wo.y == 0.0) || (wi.x == 0.0 && wi.y == 0.0)) v.diff.y = 0.0;
  return v;
}

HalfDiffAngles toHalfDiff(const Vec3d& wo, const Vec3d& wi, bool withPhiHalf) {
  const HalfDiffVectors v = halfDiffVectors(wo, wi);
  HalfDiffAngles a;
  if (v.rho > 0 && withPhiHalf) a.phiHalf = signedAzimuth(v.half);
  if (v.length > 0) a.thetaHalf = std::atan2(v.rho, v.half.z);
  const Vec3d& d = v.diff;
  a.thetaDiff = std::atan2(std::sqrt(d.x * d.x + d.y * d.y), d.z);
  a.phiDiff = signedAzimuth(d);
  return a;
}

DirectionPair fromHalfDiff(const HalfDiffAngles& a) {
  const Vec3d h = sphericalDirection(a.thetaHalf, a.phiHalf);
  const Vec3d wi = rotateZ(rotateY(sphericalDirection(a.thetaDiff, a.phiDiff), a.thetaHalf), a.phiHalf);
  // ωo is ωi reflected about h: then normalize(ωi + ωo) = h whenever ωi·h > 0.
  const double twoCos = 2.0 * (wi.x * h.x + wi.y * h.y + wi.z * h.z);
  return {{twoCos * h.x - wi.x, twoCos * h.y - wi.y, twoCos * h.z - wi.z}, wi};
}

}  // namespace acdf
