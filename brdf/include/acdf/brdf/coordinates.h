#pragma once
// Rusinkiewicz's half/difference parameterisation of a pair of directions (Rusinkiewicz, "A New
// Change of Variables for Efficient BRDF Representation", EGWR 1998), defined exactly as MERL's
// reference reader BRDFRead.cpp defines it, since that is how the MERL tables are indexed:
//
//   h = normalize(ωi + ωo)              θh = polar angle of h, φh = its azimuth
//   d = Ry(−θh) · Rz(−φh) · ωi          θd = polar angle of d, φd = its azimuth
//
// i.e. ωi is rotated by −φh about z, then by −θh about y, which carries h onto the normal; d is
// ωi seen from a frame in which the half vector is "up".
//
// On the seam. When ωi or ωo is the normal, every pair has φd = 0 or π exactly (d lies in the
// plane of the normal and h): toHalfDiff returns exactly that, MERL's φd cell 0 as BRDFRead.cpp
// gives in exact arithmetic, never a rounding residue's cell 0 or 179 at random.
//
// Directions are unit vectors in the local shading frame, z up (the normal). Computation is in
// double: near θ = 0 the angles are ill-conditioned in float, and the table lookups need the
// cell boundaries to be stable.
//
// Ranges: θh, θd in [0, π]; φh, φd in (−π, π] (atan2's range, as in MERL). For two directions in
// the upper hemisphere θh < π/2. Swapping ωi and ωo keeps θh, φh, θd and maps φd → φd + π
// (mod 2π): this is the reciprocity MERL's tables exploit by storing φd in [0, π) only.

#include "acdf/sampling/sphere.h"

namespace acdf {

struct HalfDiffAngles {
  double thetaHalf = 0, phiHalf = 0, thetaDiff = 0, phiDiff = 0;
};

struct DirectionPair {
  Vec3d wo, wi;
};

// The vectors whose angles toHalfDiff takes: h = ωi + ωo unnormalised (ρ = √(hx² + hy²) and
// |h| beside it), and d. For a lookup that finds cells from them without the angles.
struct HalfDiffVectors {
  Vec3d half;
  double rho = 0, length = 0;
  Vec3d diff;
};
HalfDiffVectors halfDiffVectors(const Vec3d& wo, const Vec3d& wi);

// (ωo, ωi) → (θh, φh, θd, φd) (pbrt's argument order, as BrdfModel::eval; d is ωi's). Both must
// be unit vectors. When ωi = −ωo the half vector is undefined; the normal is used (θh = φh = 0),
// so the result is still finite.
HalfDiffAngles toHalfDiff(const Vec3d& wo, const Vec3d& wi);
// The same, with φh left 0 unless `withPhiHalf`: an isotropic model needs θh, θd and φd only, and
// skips φh's atan2.
HalfDiffAngles toHalfDiff(const Vec3d& wo, const Vec3d& wi, bool withPhiHalf);

// The frame in which a half vector (θh, φh) points up: maps ωi to its difference angles. Holds
// the rotation's trigonometry, for loops converting many ωi against one half vector.
class HalfVectorFrame {
 public:
  HalfVectorFrame(double thetaHalf, double phiHalf);
  // The difference vector d of the unit vector ωi: ωi in this frame.
  Vec3d difference(const Vec3d& wi) const;
  // θd in [0, π] and φd in (−π, π] of the unit vector ωi (d's angles).
  void diffAngles(const Vec3d& wi, double& thetaDiff, double& phiDiff) const;
  double thetaHalf() const { return thetaHalf_; }

 private:
  double thetaHalf_;
  double cosPhi_, sinPhi_, cosTheta_, sinTheta_;  // of −φh and −θh
};

// (θh, φh, θd, φd) → (ωo, ωi): the inverse of toHalfDiff. ωi = Rz(φh)·Ry(θh)·d and ωo is ωi
// mirrored about h. Any angles give unit vectors; they lie in the upper hemisphere only when the
// angles describe such a pair (e.g. θh + θd < π/2 is always enough).
DirectionPair fromHalfDiff(const HalfDiffAngles& angles);

}  // namespace acdf
