// The tree's geometry types: Frame (frame.h), Rotation and Transform (transform.h).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "acdf/sampling/frame.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/sphere.h"
#include "acdf/sampling/transform.h"

namespace acdf {
namespace {

constexpr double kPi = std::numbers::pi;

void expectNear(const Vec3d& a, const Vec3d& b, double tolerance = 1e-14) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

Vec3d randomDirection(Pcg32& rng) { return sampleUniformSphere(rng.nextFloat(), rng.nextFloat()); }

TEST(Rotation, IsRightHanded) {
  // A quarter turn about +Z takes +X to +Y, about +Y takes +Z to +X, about +X takes +Y to +Z.
  expectNear(Rotation::aboutAxis({0, 0, 1}, kPi / 2).apply({1, 0, 0}), {0, 1, 0});
  expectNear(Rotation::aboutY(kPi / 2).apply({0, 0, 1}), {1, 0, 0});
  expectNear(Rotation::aboutAxis({2, 0, 0}, kPi / 2).apply({0, 1, 0}), {0, 0, 1});  // any axis length
}

TEST(Rotation, KeepsLengthsAndAnglesAndInvertsByItsTranspose) {
  Pcg32 rng(5);
  for (int i = 0; i < 1000; ++i) {
    const Rotation r = Rotation::aboutAxis(randomDirection(rng), 10.0 * (rng.nextFloat() - 0.5));
    const Vec3d a = randomDirection(rng) * 3.0, b = randomDirection(rng);
    const Vec3d ra = r.apply(a), rb = r.apply(b);
    EXPECT_NEAR(length(ra), 3.0, 1e-14);
    EXPECT_NEAR(dot(ra, rb), dot(a, b), 1e-14);
    expectNear(cross(ra, rb), r.apply(cross(a, b)), 1e-14);  // determinant +1: no mirror
    expectNear(r.applyInverse(ra), a, 1e-14);
  }
}

TEST(Rotation, RejectsADegenerateAxisOrAngle) {
  EXPECT_THROW(Rotation::aboutAxis({0, 0, 0}, 1.0), std::invalid_argument);
  EXPECT_THROW(Rotation::aboutAxis({NAN, 0, 1}, 1.0), std::invalid_argument);
  EXPECT_THROW(Rotation::aboutAxis({0, 1, 0}, INFINITY), std::invalid_argument);
}

TEST(Transform, ScalesThenRotatesThenTranslates) {
  const Transform t({2, 3, 4}, Rotation::aboutAxis({0, 0, 1}, kPi / 2), {10, 20, 30});
  // (1, 1, 1) scaled to (2, 3, 4), turned to (−3, 2, 4), moved to (7, 22, 34).
  expectNear(t.point({1, 1, 1}), {7, 22, 34}, 1e-13);
  expectNear(t.vector({1, 1, 1}), {-3, 2, 4}, 1e-13);  // displacements ignore the translation
  expectNear(Transform().point({1, 2, 3}), {1, 2, 3}, 0.0);
}

TEST(Frame, IsOrthonormalAndRightHandedAroundAnyNormal) {
  Pcg32 rng(9);
  for (int i = 0; i < 2000; ++i) {
    const Vec3d n = i < 4 ? Vec3d{0, 0, i % 2 ? -1.0 : 1.0} : randomDirection(rng);
    const Vec3d hint = i % 3 == 0 ? Vec3d{} : randomDirection(rng);  // none: the closed form
    const Frame f(n, hint);
    const Vec3d s = f.toWorld({1, 0, 0}), t = f.toWorld({0, 1, 0});
    expectNear(f.toWorld({0, 0, 1}), n, 0.0);
    EXPECT_NEAR(length(s), 1.0, 1e-14);
    EXPECT_NEAR(length(t), 1.0, 1e-14);
    EXPECT_NEAR(dot(s, n), 0.0, 1e-14);
    EXPECT_NEAR(dot(t, n), 0.0, 1e-14);
    expectNear(cross(s, t), n, 1e-14);
    const Vec3d v = randomDirection(rng);
    expectNear(f.toWorld(f.toLocal(v)), v, 1e-14);
  }
}

TEST(Frame, FollowsTheTangentHint) {
  const Frame f({0, 0, 1}, {1, 0, 0.5});  // the hint is orthogonalised against the normal
  expectNear(f.toWorld({1, 0, 0}), {1, 0, 0});
  expectNear(f.toWorld({0, 1, 0}), {0, 1, 0});
}

}  // namespace
}  // namespace acdf
