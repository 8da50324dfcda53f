// Rusinkiewicz half/difference coordinates: agreement with MERL's definition (an independent
// transcription using Rodrigues' rotation about an arbitrary axis and acos, from spherical
// angles, as BRDFRead.cpp does it), known configurations, round trips and reciprocity.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "acdf/brdf/coordinates.h"
#include "acdf/brdf/merl.h"

namespace {

using namespace acdf;

constexpr double kPi = std::numbers::pi;

double distance(const Vec3d& a, const Vec3d& b) { return length(a - b); }
// |a − b| as angles, modulo 2π.
double angleDistance(double a, double b) {
  const double d = std::remainder(a - b, 2 * kPi);
  return std::fabs(d);
}

// Rodrigues: v·cos + axis(axis·v)(1 − cos) + (axis × v)·sin.
Vec3d rodrigues(const Vec3d& v, const Vec3d& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle), k = dot(axis, v) * (1 - c);
  const Vec3d cross{axis.y * v.z - axis.z * v.y, axis.z * v.x - axis.x * v.z, axis.x * v.y - axis.y * v.x};
  return {v.x * c + axis.x * k + cross.x * s, v.y * c + axis.y * k + cross.y * s, v.z * c + axis.z * k + cross.z * s};
}

// MERL's std_coords_to_half_diff_coords, from the spherical angles of ωi and ωo.
HalfDiffAngles merlReference(double thetaIn, double phiIn, double thetaOut, double phiOut) {
  const Vec3d in = sphericalDirection(thetaIn, phiIn), out = sphericalDirection(thetaOut, phiOut);
  Vec3d half{(in.x + out.x) / 2, (in.y + out.y) / 2, (in.z + out.z) / 2};
  const double len = std::sqrt(dot(half, half));
  half = {half.x / len, half.y / len, half.z / len};
  HalfDiffAngles a;
  a.thetaHalf = std::acos(half.z);
  a.phiHalf = std::atan2(half.y, half.x);
  const Vec3d diff = rodrigues(rodrigues(in, {0, 0, 1}, -a.phiHalf), {0, 1, 0}, -a.thetaHalf);
  a.thetaDiff = std::acos(diff.z);
  a.phiDiff = std::atan2(diff.y, diff.x);
  return a;
}

struct Hemisphere {
  std::mt19937_64 rng{20261122};
  std::uniform_real_distribution<double> u{0.0, 1.0};
  // Uniform on the open upper hemisphere (z in (0, 1]).
  Vec3d direction(double* theta = nullptr, double* phi = nullptr) {
    const double z = 1.0 - u(rng) * 0.999999;
    const double t = std::acos(z), p = (2 * u(rng) - 1) * kPi;
    if (theta) *theta = t;
    if (phi) *phi = p;
    return sphericalDirection(t, p);
  }
};

TEST(Coordinates, NormalIncidenceIsAllZero) {
  const HalfDiffAngles a = toHalfDiff({0, 0, 1}, {0, 0, 1});
  EXPECT_EQ(a.thetaHalf, 0.0);
  EXPECT_EQ(a.thetaDiff, 0.0);
  EXPECT_EQ(a.phiHalf, 0.0);
}

// With either direction on the normal every pair lies on MERL's φd seam (the plane of the normal
// and h contains both): φd exactly 0 or ±π, never a rounding residue of either sign, so MERL's φd
// cell is 0 for every such pair, as BRDFRead.cpp gives in exact arithmetic.
TEST(Coordinates, NormalIncidenceLiesExactlyOnThePhiDiffSeam) {
  Hemisphere hemisphere;
  for (int n = 0; n < 100000; ++n) {
    const Vec3d w = hemisphere.direction();
    for (const auto& [wi, wo] : {std::pair{w, Vec3d{0, 0, 1}}, std::pair{Vec3d{0, 0, 1}, w}}) {
      const HalfDiffAngles a = toHalfDiff(wo, wi);
      ASSERT_TRUE(a.phiDiff == 0.0 || std::abs(a.phiDiff) == kPi)
          << a.phiDiff << ": " << wi.x << " " << wi.y << " " << wi.z << " / " << wo.x << " " << wo.y << " " << wo.z;
      ASSERT_NEAR(a.thetaDiff, polarAngle(w) / 2, 1e-12);
      ASSERT_NEAR(a.thetaHalf, polarAngle(w) / 2, 1e-12);
    }
  }
}

TEST(Coordinates, RetroreflectionHasZeroThetaDiff) {
  // ωi = ωo: the half vector is ωi itself, and d is the normal.
  for (double theta : {0.1, 0.7, 1.3}) {
    for (double phi : {-2.5, 0.0, 1.0, 3.0}) {
      const Vec3d w = sphericalDirection(theta, phi);
      const HalfDiffAngles a = toHalfDiff(w, w);
      EXPECT_NEAR(a.thetaHalf, theta, 1e-12);
      EXPECT_NEAR(angleDistance(a.phiHalf, phi), 0.0, 1e-12);
      EXPECT_NEAR(a.thetaDiff, 0.0, 1e-7);
    }
  }
}

TEST(Coordinates, MirrorPairHasHalfVectorAtTheNormal) {
  // ωo the mirror direction of ωi: h = normal, so d = ωi rotated by −φh (θd = θi). φh itself is
  // whatever rounding leaves in h's x and y (MERL's is too), so check φh + φd = φi.
  for (double theta : {0.2, 0.9, 1.5}) {
    for (double phi : {-3.0, -0.5, 0.4, 2.0}) {
      const Vec3d wi = sphericalDirection(theta, phi), wo = sphericalDirection(theta, phi + kPi);
      const HalfDiffAngles a = toHalfDiff(wo, wi);
      EXPECT_NEAR(a.thetaHalf, 0.0, 1e-12);
      EXPECT_NEAR(a.thetaDiff, theta, 1e-12);
      EXPECT_NEAR(angleDistance(a.phiHalf + a.phiDiff, phi), 0.0, 1e-12);
    }
  }
}

TEST(Coordinates, InPlaneExample) {
  // ωi at 60° on the +x side, ωo straight up: h at 30° on the +x side, d at 30° from it, towards +x.
  const HalfDiffAngles a = toHalfDiff({0, 0, 1}, sphericalDirection(kPi / 3, 0));
  EXPECT_NEAR(a.thetaHalf, kPi / 6, 1e-12);
  EXPECT_NEAR(a.phiHalf, 0.0, 1e-12);
  EXPECT_NEAR(a.thetaDiff, kPi / 6, 1e-12);
  EXPECT_NEAR(a.phiDiff, 0.0, 1e-12);
}

TEST(Coordinates, MatchesMerlReferenceOnRandomPairs) {
  Hemisphere gen;
  for (int n = 0; n < 20000; ++n) {
    double ti, pi, to, po;
    const Vec3d wi = gen.direction(&ti, &pi), wo = gen.direction(&to, &po);
    const HalfDiffAngles a = toHalfDiff(wo, wi), r = merlReference(ti, pi, to, po);
    ASSERT_NEAR(a.thetaHalf, r.thetaHalf, 1e-7) << n;
    ASSERT_NEAR(a.thetaDiff, r.thetaDiff, 1e-7) << n;
    // Azimuths are ill-conditioned at the pole; compare them where they mean something.
    if (r.thetaHalf > 1e-4) {
      ASSERT_NEAR(angleDistance(a.phiHalf, r.phiHalf), 0.0, 1e-7) << n;
    }
    if (r.thetaDiff > 1e-4) {
      ASSERT_NEAR(angleDistance(a.phiDiff, r.phiDiff), 0.0, 1e-7) << n;
    }
  }
}

// toHalfDiff as it was written first: the rotation by the cosines and sines of the angles
// atan2 gave, Ry(−θh) · Rz(−φh), instead of ratios of h's components.
HalfDiffAngles rotatedByAngles(const Vec3d& wo, const Vec3d& wi) {
  const Vec3d sum = wi + wo;
  HalfDiffAngles a;
  if (sum.x != 0 || sum.y != 0 || sum.z != 0) {
    a.thetaHalf = polarAngle(sum);
    a.phiHalf = std::atan2(sum.y, sum.x);
  }
  const double cp = std::cos(-a.phiHalf), sp = std::sin(-a.phiHalf);
  const double ct = std::cos(-a.thetaHalf), st = std::sin(-a.thetaHalf);
  const Vec3d r{cp * wi.x - sp * wi.y, sp * wi.x + cp * wi.y, wi.z};
  Vec3d d{ct * r.x + st * r.z, r.y, ct * r.z - st * r.x};
  if ((wo.x == 0.0 && wo.y == 0.0) || (wi.x == 0.0 && wi.y == 0.0)) d.y = 0.0;
  a.thetaDiff = polarAngle(d);
  a.phiDiff = std::atan2(d.y, d.x);
  return a;
}

// The conversion without trigonometric functions looks up the same MERL cells as the rotation by
// the angles on random pairs, on pairs with a direction at the normal (the φd seam), near the
// mirror direction (θh near 0) and at grazing angles; only rounding differs (angles within
// 1e-12, θh within 1e-15: a square root instead of hypot), so a cell can differ only for angles
// within that of a cell boundary, which none of these pairs is.
TEST(Coordinates, ComponentRotationLooksUpTheSameMerlCells) {
#ifdef ACDF_SANITIZED_BUILD
  const int pairs = 20000;
#else
  const int pairs = 100000;
#endif
  Hemisphere gen;
  std::uniform_real_distribution<double> tiny(-1e-6, 1e-6);
  int differentCells = 0;
  for (int n = 0; n < pairs; ++n) {
    Vec3d wo = gen.direction(), wi = gen.direction();
    switch (n % 4) {
      case 1: wo = {0, 0, 1}; break;                                                             // at the normal
      case 2: wi = normalize(Vec3d{-wo.x + tiny(gen.rng), -wo.y + tiny(gen.rng), wo.z}); break;  // near mirror
      case 3: wi = normalize(Vec3d{wi.x, wi.y, 1e-4 * wi.z}); break;                             // grazing
      default: break;
    }
    const HalfDiffAngles a = toHalfDiff(wo, wi), r = rotatedByAngles(wo, wi);
    ASSERT_NEAR(a.thetaHalf, r.thetaHalf, 1e-15) << n;
    ASSERT_NEAR(a.thetaDiff, r.thetaDiff, 1e-12) << n;
    if (a.thetaDiff > 1e-6) {
      ASSERT_NEAR(angleDistance(a.phiDiff, r.phiDiff), 0.0, 1e-9) << n;
    }
    differentCells += MerlBrdf::thetaHalfIndex(a.thetaHalf) != MerlBrdf::thetaHalfIndex(r.thetaHalf) ||
                      MerlBrdf::thetaDiffIndex(a.thetaDiff) != MerlBrdf::thetaDiffIndex(r.thetaDiff) ||
                      MerlBrdf::phiDiffIndex(a.phiDiff) != MerlBrdf::phiDiffIndex(r.phiDiff);
    // Without φh, the rest is the same.
    const HalfDiffAngles isotropic = toHalfDiff(wo, wi, false);
    ASSERT_EQ(isotropic.phiHalf, 0.0);
    ASSERT_EQ(isotropic.thetaHalf, a.thetaHalf);
    ASSERT_EQ(isotropic.thetaDiff, a.thetaDiff);
    ASSERT_EQ(isotropic.phiDiff, a.phiDiff);
  }
  EXPECT_EQ(differentCells, 0);
}

TEST(Coordinates, DirectionsRoundTrip) {
  Hemisphere gen;
  double worst = 0;
  for (int n = 0; n < 100000; ++n) {
    const Vec3d wi = gen.direction(), wo = gen.direction();
    const DirectionPair back = fromHalfDiff(toHalfDiff(wo, wi));
    worst = std::max({worst, distance(back.wi, wi), distance(back.wo, wo)});
  }
  EXPECT_LT(worst, 1e-5);
  RecordProperty("worst_direction_error", std::to_string(worst));
}

TEST(Coordinates, AnglesRoundTrip) {
  // Angles of upper-hemisphere pairs → directions → angles.
  Hemisphere gen;
  for (int n = 0; n < 100000; ++n) {
    const HalfDiffAngles a = toHalfDiff(gen.direction(), gen.direction());
    const DirectionPair p = fromHalfDiff(a);
    ASSERT_GT(p.wi.z, -1e-12);
    ASSERT_GT(p.wo.z, -1e-12);
    const HalfDiffAngles b = toHalfDiff(p.wo, p.wi);
    ASSERT_NEAR(b.thetaHalf, a.thetaHalf, 1e-5) << n;
    ASSERT_NEAR(b.thetaDiff, a.thetaDiff, 1e-5) << n;
    if (a.thetaHalf > 1e-3) {
      ASSERT_NEAR(angleDistance(b.phiHalf, a.phiHalf), 0.0, 1e-5) << n;
    }
    if (a.thetaDiff > 1e-3) {
      ASSERT_NEAR(angleDistance(b.phiDiff, a.phiDiff), 0.0, 1e-5) << n;
    }
  }
}

TEST(Coordinates, FromHalfDiffGivesUnitVectorsWithThatHalfVector) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n = 0; n < 10000; ++n) {
    const HalfDiffAngles a{u(rng) * kPi / 2, (2 * u(rng) - 1) * kPi, u(rng) * kPi / 2, (2 * u(rng) - 1) * kPi};
    const DirectionPair p = fromHalfDiff(a);
    ASSERT_NEAR(dot(p.wi, p.wi), 1.0, 1e-12);
    ASSERT_NEAR(dot(p.wo, p.wo), 1.0, 1e-12);
    const Vec3d sum{p.wi.x + p.wo.x, p.wi.y + p.wo.y, p.wi.z + p.wo.z};
    const double len = std::sqrt(dot(sum, sum));
    if (len < 1e-6) continue;  // θd = π/2: ωo = −ωi, no half vector
    const Vec3d h = sphericalDirection(a.thetaHalf, a.phiHalf);
    ASSERT_NEAR(dot(sum, h) / len, 1.0, 1e-9) << n;
  }
}

TEST(Coordinates, ReciprocityShiftsPhiDiffByPi) {
  Hemisphere gen;
  for (int n = 0; n < 100000; ++n) {
    const Vec3d wi = gen.direction(), wo = gen.direction();
    const HalfDiffAngles a = toHalfDiff(wo, wi), b = toHalfDiff(wi, wo);
    ASSERT_NEAR(b.thetaHalf, a.thetaHalf, 1e-12) << n;
    ASSERT_NEAR(b.thetaDiff, a.thetaDiff, 1e-12) << n;
    if (a.thetaDiff > 1e-6) {
      ASSERT_NEAR(angleDistance(b.phiDiff, a.phiDiff + kPi), 0.0, 1e-7) << n;
    }
  }
}

TEST(Coordinates, OppositeDirectionsStayFinite) {
  // No half vector: the normal stands in for it.
  const Vec3d w = sphericalDirection(kPi / 2, 0.3);
  const HalfDiffAngles a = toHalfDiff({-w.x, -w.y, -w.z}, w);
  EXPECT_EQ(a.thetaHalf, 0.0);
  EXPECT_EQ(a.phiHalf, 0.0);
  EXPECT_NEAR(a.thetaDiff, kPi / 2, 1e-12);
  EXPECT_NEAR(angleDistance(a.phiDiff, 0.3), 0.0, 1e-12);
}

}  // namespace
