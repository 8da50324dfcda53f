// OutgoingCells: the cells (and the slice) it finds without trigonometry are those of the angles
// (cellsFromAngles) for every direction, in particular at a few ulps around every cell boundary, at the poles, on
// and below the horizon, on the seam φ = 0 = 2π, and for directions that are not unit vectors.

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
  if (phiCells) EXPECT_EQ(phiSeen.size(), *phiCells);

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

}  // namespace
