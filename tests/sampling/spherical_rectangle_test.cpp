// SphericalRectangle: its solid angle against closed forms and additivity, every sample through
// the rectangle with the pdf it reports (extreme variates included), the pdf integrating to 1 over
// the sphere, and a chi-square test over cells of the rectangle whose probabilities are their own
// solid angles.

#include "acdf/sampling/spherical_rectangle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "acdf/sampling/chi_square.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/sample.h"
#include "acdf/test_support/chi_square_registry.h"

namespace {

using namespace acdf;

struct Rectangle {
  Vec3d corner, edgeU, edgeV;
};

// A window 1.4 × 1.1 in the plane z = 2, edges along x and y, and one tilted in 3D.
const Rectangle kWindow{{-0.7, 0.9, 2.0}, {1.4, 0, 0}, {0, 1.1, 0}};
const Rectangle kTilted{
    {0.3, -0.2, 0.5}, Vec3d{1.0, 0.5, 0.2} * 0.8, normalize(cross({1.0, 0.5, 0.2}, {0, 0, 1})) * 0.5};

// Origins: in front of the window, far off its axis, close to its plane (grazing), behind it.
const Vec3d kOrigins[] = {{0.1, 1.3, -1.5}, {-1.8, 0.2, 1.2}, {0.4, 1.6, 1.999}, {0.3, 1.0, 3.0}};

TEST(SphericalRectangle, SolidAngleMatchesTheClosedFormAndAddsUp) {
  // A 2 × 2 square centred 1 below: Ω = 4 arcsin(ab / √((a² + 4d²)(b² + 4d²))) = 4 arcsin(1/2).
  const SphericalRectangle square({0, 0, 1}, {-1, -1, 0}, {2, 0, 0}, {0, 2, 0});
  EXPECT_NEAR(square.solidAngle(), 2.0 * std::numbers::pi / 3.0, 1e-14);
  // Four quarters of the window seen from any point add up to the whole.
  for (const Vec3d& o : kOrigins) {
    const Rectangle& w = kWindow;
    double quarters = 0;
    for (double s : {0.0, 0.5})
      for (double t : {0.0, 0.5})
        quarters += SphericalRectangle(o, w.corner + w.edgeU * s + w.edgeV * t, w.edgeU * 0.5, w.edgeV * 0.5)
                        .solidAngle();
    const double whole = SphericalRectangle(o, w.corner, w.edgeU, w.edgeV).solidAngle();
    EXPECT_GT(whole, 0.0);
    EXPECT_NEAR(quarters, whole, 1e-12 * whole);
  }
}

TEST(SphericalRectangle, SolidAngleOfAloneAgreesAndKeepsItsPrecisionFarAway) {
  for (const Rectangle& r : {kWindow, kTilted})
    for (const Vec3d& o : kOrigins) {
      const double omega = SphericalRectangle(o, r.corner, r.edgeU, r.edgeV).solidAngle();
      EXPECT_NEAR(SphericalRectangle::solidAngleOf(o, r.corner, r.edgeU, r.edgeV), omega, 1e-13 * omega);
    }
  EXPECT_EQ(SphericalRectangle::solidAngleOf({5, 1, 2}, kWindow.corner, kWindow.edgeU, kWindow.edgeV), 0.0)
      << "an origin in the plane";
  // A 2 × 2 square centred d below, against the closed form 4 arcsin(1 / (1 + d²)): at d = 1 and
  // where the four-angle construction has lost half its digits (d = 10⁴: Ω ≈ 4·10⁻⁸).
  for (const double d : {1.0, 30.0, 1e4}) {
    const double exact = 4.0 * std::asin(1.0 / (1.0 + d * d));
    EXPECT_NEAR(SphericalRectangle::solidAngleOf({0, 0, d}, {-1, -1, 0}, {2, 0, 0}, {0, 2, 0}), exact, 1e-14 * exact)
        << d;
  }
}

TEST(SphericalRectangle, SolidAngleEqualsTheIntegralOverTheArea) {
  // ∫ cos θ / r² dA by the midpoint rule on 1000 × 1000 cells.
  for (const Rectangle& r : {kWindow, kTilted}) {
    const Vec3d o = kOrigins[0];
    const Vec3d n = normalize(cross(r.edgeU, r.edgeV));
    const int cells = 1000;
    const double area = length(r.edgeU) * length(r.edgeV) / (cells * cells);
    double integral = 0;
    for (int i = 0; i < cells; ++i)
      for (int j = 0; j < cells; ++j) {
        const Vec3d d = r.corner + r.edgeU * ((i + 0.5) / cells) + r.edgeV * ((j + 0.5) / cells) - o;
        const double r2 = dot(d, d);
        integral += std::abs(dot(d, n)) / (r2 * std::sqrt(r2)) * area;
      }
    EXPECT_NEAR(SphericalRectangle(o, r.corner, r.edgeU, r.edgeV).solidAngle(), integral, 1e-6 * integral);
  }
}

TEST(SphericalRectangle, EverySampleGoesThroughWithThePdfItReports) {
  const float extremes[] = {0.0f, 1e-7f, 0.5f, kOneMinusEpsilon};
  Pcg32 rng(7);
  for (const Rectangle& r : {kWindow, kTilted})
    for (const Vec3d& o : kOrigins) {
      const SphericalRectangle rect(o, r.corner, r.edgeU, r.edgeV);
      ASSERT_FALSE(rect.empty());
      std::vector<std::array<double, 2>> variates;
      for (float a : extremes)
        for (float b : extremes) variates.push_back({a, b});
      variates.push_back({1.0, 1.0});
      for (int k = 0; k < 20000; ++k) variates.push_back({rng.nextFloat(), rng.nextFloat()});
      for (const auto& [u0, u1] : variates) {
        const DirectionSample s = rect.sample(u0, u1);
        ASSERT_NEAR(length(s.direction), 1.0, 1e-12) << u0 << ", " << u1;
        ASSERT_EQ(s.pdf, 1.0 / rect.solidAngle());
        ASSERT_EQ(rect.pdf(s.direction), s.pdf) << u0 << ", " << u1;
      }
    }
}

TEST(SphericalRectangle, PdfIsZeroAwayFromTheRectangleAndIntegratesToOne) {
  const SphericalRectangle rect(kOrigins[0], kWindow.corner, kWindow.edgeU, kWindow.edgeV);
  EXPECT_EQ(rect.pdf({0, 0, -1}), 0.0) << "away from the plane";
  EXPECT_EQ(rect.pdf({1, 0, 0}), 0.0) << "parallel to the plane";
  EXPECT_EQ(rect.pdf({0, 0, 0}), 0.0);
  // 4π × the mean pdf of uniform directions: 1 within 5 standard errors.
  Pcg32 rng(11);
  const int n = 1'000'000;
  double sum = 0;
  for (int k = 0; k < n; ++k) sum += rect.pdf(sampleUniformSphere(rng.nextFloat(), rng.nextFloat()));
  const double integral = 4.0 * std::numbers::pi * sum / n;
  const double p = rect.solidAngle() / (4.0 * std::numbers::pi);
  EXPECT_NEAR(integral, 1.0, 5.0 * std::sqrt((1.0 - p) / (p * n)));
}

TEST(SphericalRectangle, OriginInThePlaneSeesNothingAndBadEdgesAreRefused) {
  const SphericalRectangle flat({5, 1, 2}, kWindow.corner, kWindow.edgeU, kWindow.edgeV);
  EXPECT_TRUE(flat.empty());
  EXPECT_EQ(flat.sample(0.5, 0.5).pdf, 0.0);
  EXPECT_EQ(flat.pdf({0, 0, 1}), 0.0);
  EXPECT_THROW(SphericalRectangle({0, 0, 0}, {0, 0, 1}, {0, 0, 0}, {0, 1, 0}), std::invalid_argument);
  EXPECT_THROW(SphericalRectangle({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {1, 1, 0}), std::invalid_argument);
  EXPECT_THROW(SphericalRectangle({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, NAN, 0}), std::invalid_argument);
}

// 10⁶ samples binned by where they cross the rectangle, on 32 × 32 cells; a cell's probability is
// its own solid angle over the whole's, so the test needs no quadrature.
ACDF_CHI_SQUARE_TEST(SphericalRectangle, ChiSquareOverCellsOfTheRectangle, 4) {
  const int cells = 32;
  for (const Vec3d& o : kOrigins) {
    const Rectangle& r = kWindow;
    const SphericalRectangle rect(o, r.corner, r.edgeU, r.edgeV);
    std::vector<double> expected(cells * cells), observed(cells * cells, 0.0);
    const int n = 1'000'000;
    for (int i = 0; i < cells; ++i)
      for (int j = 0; j < cells; ++j)
        expected[i * cells + j] = n *
                                  SphericalRectangle(o, r.corner + r.edgeU * (double(i) / cells) +
                                                            r.edgeV * (double(j) / cells),
                                                     r.edgeU * (1.0 / cells), r.edgeV * (1.0 / cells))
                                      .solidAngle() /
                                  rect.solidAngle();
    Pcg32 rng(17);
    const Vec3d normal = normalize(cross(r.edgeU, r.edgeV));
    for (int k = 0; k < n; ++k) {
      const Vec3d w = rect.sample(rng.nextFloat(), rng.nextFloat()).direction;
      const Vec3d hit = o + w * (dot(r.corner - o, normal) / dot(w, normal)) - r.corner;
      const int i = std::clamp(static_cast<int>(dot(hit, r.edgeU) / dot(r.edgeU, r.edgeU) * cells), 0, cells - 1);
      const int j = std::clamp(static_cast<int>(dot(hit, r.edgeV) / dot(r.edgeV, r.edgeV) * cells), 0, cells - 1);
      observed[i * cells + j] += 1;
    }
    const ChiSquareResult result = chiSquareTest(observed, expected);
    EXPECT_GE(result.pvalue, test_support::chiSquareTestLevel())
        << "origin " << o.x << ", " << o.y << ", " << o.z << ": chi2 " << result.statistic << " dof " << result.dof;
  }
}

}  // namespace
