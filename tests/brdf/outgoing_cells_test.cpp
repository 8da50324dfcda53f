// OutgoingCells: the cells (and the slice) it finds without trigonometry are those of the angles
// (cellsFromAngles) for every direction, in particular at a few ulps around every cell boundary, at the poles, on
// and below the horizon, on the seam φ = 0 = 2π, and for directions that are not unit vectors.
// HalfVectorCells: the same for half vectors given ωo, in every azimuth layout (φh, Δφ, |Δφ|): random pairs,
// a few ulps around every θh and azimuth cell boundary, Δφ near 0 and π, and either direction at the normal.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <vector>

#include "acdf/brdf/outgoing_cells.h"

namespace {

using namespace acdf;

constexpr double kPi = std::numbers::pi;

struct Checker {
  const OutgoingCells& cells;
  uint32_t phiCells;  // 1 without a φo axis
  int mismatches = 0;

  void check(const Vec3d& wo) {
    const std::array<uint32_t, 2> fast = cells.cellsOf(wo), exact = cells.cellsFromAngles(wo);
    // The slice a Cascade with these conditioning axes would find: row-major, φo fastest.
    const std::size_t slice = cells.sliceOf(wo), exactSlice = std::size_t{exact[0]} * phiCells + exact[1];
    if (fast == exact && slice == exactSlice) return;
    if (++mismatches <= 10)
      ADD_FAILURE() << std::hexfloat << "wo = (" << wo.x << ", " << wo.y << ", " << wo.z << "): cells " << fast[0]
                    << ", " << fast[1] << ", slice " << slice << " instead of " << exact[0] << ", " << exact[1]
                    << ", slice " << exactSlice;
  }
  // wo and its neighbours one ulp away in each component.
  void checkAround(const Vec3d& wo) {
    const auto around = [](double v) {
      return std::array<double, 3>{std::nextafter(v, -INFINITY), v, std::nextafter(v, INFINITY)};
    };
    for (double x : around(wo.x))
      for (double y : around(wo.y))
        for (double z : around(wo.z)) check({x, y, z});
  }
};

// The angles, in double, a few ulps either side of where the angle's float coordinate enters
// each cell k >= 1 of the axis: the midpoint between the cell's first float and the one below.
std::vector<double> anglesAroundBoundaries(const GridAxis& axis) {
  std::vector<double> angles;
  for (uint32_t k = 1; k < axis.cells(); ++k) {
    float first = static_cast<float>(k * axis.cellWidth());
    while (axis.cellOf(first) >= k) first = std::nextafter(first, 0.0f);
    while (axis.cellOf(first) < k) first = std::nextafter(first, INFINITY);
    const double mid = 0.5 * (static_cast<double>(std::nextafter(first, 0.0f)) + first);
    double below = mid, above = mid;
    angles.push_back(mid);
    for (int i = 0; i < 4; ++i) {
      angles.push_back(below = std::nextafter(below, 0.0));
      angles.push_back(above = std::nextafter(above, INFINITY));
    }
    angles.push_back(first);
    angles.push_back(std::nextafter(first, 0.0f));
  }
  return angles;
}

void checkAxes(uint32_t thetaCells, std::optional<uint32_t> phiCells) {
  const GridAxis thetaAxis(thetaCells, 0.0f, static_cast<float>(0.5 * kPi));
  const std::optional<GridAxis> phiAxis =
      phiCells ? std::optional<GridAxis>(GridAxis(*phiCells, 0.0f, static_cast<float>(2.0 * kPi))) : std::nullopt;
  const OutgoingCells cells(thetaAxis, phiAxis);
  Checker checker{cells, phiCells.value_or(1)};
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  // Uniform on the sphere, the lower hemisphere included, and some not of unit length.
  for (int i = 0; i < 1'000'000; ++i) {
    const Vec3d wo = sphericalDirection(std::acos(1.0 - 2.0 * unit(rng)), 2.0 * kPi * unit(rng));
    checker.check(wo);
    if (i % 16 == 0) checker.check(wo * (0.25 + 4.0 * unit(rng)));
  }

  // Around every θo boundary, at random φo and at the φo boundaries; both sides must be seen.
  const std::vector<double> thetas = anglesAroundBoundaries(thetaAxis);
  const std::vector<double> phis = phiAxis ? anglesAroundBoundaries(*phiAxis) : std::vector<double>{};
  std::set<uint32_t> thetaSeen;
  for (double theta : thetas) {
    for (int i = 0; i < 8; ++i) {
      const Vec3d wo = sphericalDirection(theta, 2.0 * kPi * unit(rng));
      checker.checkAround(wo);
      thetaSeen.insert(cells.cellsFromAngles(wo)[0]);
    }
    for (std::size_t j = 0; j < phis.size(); j += 5) checker.checkAround(sphericalDirection(theta, phis[j]));
  }
  EXPECT_EQ(thetaSeen.size(), thetaCells);
  // Around every φo boundary, at random θo.
  std::set<uint32_t> phiSeen;
  for (double phi : phis)
    for (int i = 0; i < 8; ++i) {
      const Vec3d wo = sphericalDirection(0.5 * kPi * unit(rng), phi);
      checker.checkAround(wo);
      phiSeen.insert(cells.cellsFromAngles(wo)[1]);
    }
  if (phiCells) {
    EXPECT_EQ(phiSeen.size(), *phiCells);
  }

  // Poles, horizon, the seam φo = 0 = 2π and φo = π, signed zeros, tiny and huge scales, NaN.
  const double tiny = std::numeric_limits<double>::denorm_min(), eps = 1e-300;
  for (double x : {0.0, -0.0, tiny, -tiny, eps, -eps, 1e-9, -1e-9, 1.0, -1.0})
    for (double y : {0.0, -0.0, tiny, -tiny, eps, -eps, 1e-17, -1e-17, 1e-9, -1e-9, 1.0, -1.0})
      for (double z : {1.0, 0.5, 1e-9, tiny, 0.0, -0.0, -tiny, -1.0}) checker.checkAround({x, y, z});
  for (double scale : {1e-300, 1e-160, 1e-150, 1e150, 1e160, 1e300, 0x1p-1074})
    for (int i = 0; i < 1000; ++i)
      checker.check(sphericalDirection(0.5 * kPi * unit(rng), 2.0 * kPi * unit(rng)) * scale);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const Vec3d& wo : {Vec3d{nan, 0, 1}, Vec3d{0, nan, 1}, Vec3d{0, 0, nan}, Vec3d{inf, 0, 1}, Vec3d{1, inf, 1},
                          Vec3d{0, 0, inf}, Vec3d{-inf, -inf, inf}})
    checker.check(wo);
  EXPECT_EQ(checker.mismatches, 0);
}

TEST(OutgoingCells, FullLayoutCellsAreThoseOfTheAngles) { checkAxes(32, 16); }
TEST(OutgoingCells, IsotropicLayoutCellsAreThoseOfTheAngles) { checkAxes(32, std::nullopt); }
TEST(OutgoingCells, OddCellCountsAreThoseOfTheAngles) { checkAxes(7, 5); }

struct HalfChecker {
  const HalfVectorCells& cells;
  int mismatches = 0;

  void check(const Vec3d& wo, const Vec3d& wh) {
    const std::array<uint32_t, 2> fast = cells.cellsOf(wo, wh), exact = cells.cellsFromAngles(wo, wh);
    if (fast == exact) return;
    if (++mismatches <= 10)
      ADD_FAILURE() << std::hexfloat << "wo = (" << wo.x << ", " << wo.y << ", " << wo.z << "), wh = (" << wh.x << ", "
                    << wh.y << ", " << wh.z << "): cells " << fast[0] << ", " << fast[1] << " instead of " << exact[0]
                    << ", " << exact[1];
  }
  // wh and its neighbours one ulp away in each component.
  void checkAround(const Vec3d& wo, const Vec3d& wh) {
    const auto around = [](double v) {
      return std::array<double, 3>{std::nextafter(v, -INFINITY), v, std::nextafter(v, INFINITY)};
    };
    for (double x : around(wh.x))
      for (double y : around(wh.y))
        for (double z : around(wh.z)) check(wo, {x, y, z});
  }
};

// θh in double a few ulps either side of each boundary (k / cells)² · π/2 of the s cells.
std::vector<double> thetaHalvesAroundBoundaries(uint32_t sCells) {
  std::vector<double> angles;
  for (uint32_t k = 1; k < sCells; ++k) {
    const double s = static_cast<double>(k) / sCells, boundary = s * s * 0.5 * kPi;
    double below = boundary, above = boundary;
    angles.push_back(boundary);
    for (int i = 0; i < 8; ++i) {
      angles.push_back(below = std::nextafter(below, 0.0));
      angles.push_back(above = std::nextafter(above, INFINITY));
    }
  }
  return angles;
}

void checkHalfVectorAxes(uint32_t sCells, uint32_t phiCells, HalfAzimuth layout) {
  const bool folded = layout == HalfAzimuth::Folded;
  const GridAxis sAxis(sCells, 0.0f, 1.0f);
  const GridAxis phiAxis(phiCells, 0.0f, static_cast<float>(folded ? kPi : 2.0 * kPi));
  const HalfVectorCells cells(sAxis, phiAxis, layout);
  HalfChecker checker{cells};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto upper = [&] { return sphericalDirection(0.5 * kPi * unit(rng), 2.0 * kPi * unit(rng)); };
  // ωh at θh and at an azimuth φ of the layout's: φh itself, or Δφ (either sign when folded) from ωo's.
  const auto halfVector = [&](const Vec3d& wo, double thetaHalf, double phi) {
    if (layout == HalfAzimuth::Absolute) return sphericalDirection(thetaHalf, phi);
    return sphericalDirection(thetaHalf, azimuth(wo) + (folded && unit(rng) < 0.5 ? -phi : phi));
  };

  // Random pairs in the upper hemisphere, some not of unit length.
  for (int i = 0; i < 2'000'000; ++i) {
    const Vec3d wo = upper(), wh = upper();
    checker.check(wo, wh);
    if (i % 16 == 0) checker.check(wo * (0.25 + 4.0 * unit(rng)), wh * (0.25 + 4.0 * unit(rng)));
  }

  // Around every θh boundary at random azimuths; both sides must be seen.
  std::set<uint32_t> sSeen, phiSeen;
  for (double theta : thetaHalvesAroundBoundaries(sCells))
    for (int i = 0; i < 4; ++i) {
      const Vec3d wo = upper(), wh = sphericalDirection(theta, 2.0 * kPi * unit(rng));
      checker.checkAround(wo, wh);
      sSeen.insert(cells.cellsFromAngles(wo, wh)[0]);
    }
  EXPECT_EQ(sSeen.size(), sCells);
  // Around every azimuth boundary, and around Δφ = 0 and π (the seam and the fold), at random θh.
  std::vector<double> phis = anglesAroundBoundaries(phiAxis);
  for (double phi : {0.0, 1e-17, 1e-16, 1e-15, 1e-12, 1e-10, kPi, std::nextafter(kPi, 0.0), kPi + 1e-15}) {
    phis.push_back(phi);
    phis.push_back(-phi);
  }
  for (double phi : phis)
    for (int i = 0; i < 8; ++i) {
      const Vec3d wo = upper(), wh = halfVector(wo, 0.5 * kPi * unit(rng), phi);
      checker.checkAround(wo, wh);
      phiSeen.insert(cells.cellsFromAngles(wo, wh)[1]);
    }
  EXPECT_EQ(phiSeen.size(), phiCells);

  // Either direction at or near the normal (no azimuth), signed zeros, tiny and huge scales.
  const double tiny = std::numeric_limits<double>::denorm_min();
  const std::vector<Vec3d> poles = {{0, 0, 1},     {-0.0, 0, 1},        {0, -0.0, 1},     {-0.0, -0.0, 1}, {tiny, 0, 1},
                                    {0, -tiny, 1}, {1e-160, 1e-160, 1}, {1e-9, -1e-9, 1}, {0, 0, 1e-300}};
  for (const Vec3d& pole : poles)
    for (int i = 0; i < 100; ++i) {
      const Vec3d other = upper();
      checker.checkAround(other, pole);
      checker.checkAround(pole, other);
      checker.check(pole, pole);
    }
  for (double scale : {1e-300, 1e-160, 1e-150, 1e150, 1e160, 1e300})
    for (int i = 0; i < 1000; ++i) {
      checker.check(upper() * scale, upper());
      checker.check(upper(), upper() * scale);
    }
  EXPECT_EQ(checker.mismatches, 0);
}

TEST(HalfVectorCells, FullLayoutCellsAreThoseOfTheAngles) { checkHalfVectorAxes(256, 32, HalfAzimuth::Absolute); }
TEST(HalfVectorCells, IsotropicLayoutCellsAreThoseOfTheAngles) { checkHalfVectorAxes(256, 32, HalfAzimuth::Relative); }
TEST(HalfVectorCells, MirroredLayoutCellsAreThoseOfTheAngles) { checkHalfVectorAxes(256, 16, HalfAzimuth::Folded); }
TEST(HalfVectorCells, OddCellCountsAreThoseOfTheAngles) {
  checkHalfVectorAxes(7, 5, HalfAzimuth::Absolute);
  checkHalfVectorAxes(7, 5, HalfAzimuth::Relative);
  checkHalfVectorAxes(7, 5, HalfAzimuth::Folded);
}

}  // namespace
