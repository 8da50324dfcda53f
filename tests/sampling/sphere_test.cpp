// Directions (sphere.h) and the spherical chi-square test (sphere_chi_square.h): the warps pass
// against their closed-form pdfs, and the test rejects a wrong pdf, a wrongly distributed sampler,
// an inconsistent returned pdf and invalid directions.

#include "acdf/sampling/sphere_chi_square.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "acdf/sampling/sample.h"
#include "acdf/test_support/chi_square_registry.h"

namespace {

using namespace acdf;
using test_support::chiSquareTestLevel;

// The options of one chi-square test whose verdict is checked: its level in this program's family.
SphereChiSquareOptions options() {
  SphereChiSquareOptions o;
  o.alpha = chiSquareTestLevel();
  return o;
}

DirectionSample uniformSphere(float u0, float u1) { return {sampleUniformSphere(u0, u1), kUniformSpherePdf}; }
double uniformSpherePdf(const Vec3d&) { return kUniformSpherePdf; }

DirectionSample cosineHemisphere(float u0, float u1) {
  const Vec3d w = sampleCosineHemisphere(u0, u1);
  return {w, cosineHemispherePdf(w.z)};
}
double cosinePdf(const Vec3d& w) { return cosineHemispherePdf(w.z); }

TEST(Sphere, SphericalCoordinatesRoundTrip) {
  for (double theta : {1e-9, 0.3, 1.5707963, 2.9, std::numbers::pi - 1e-9})
    for (double phi : {0.0, 1.0, 3.14159, 4.0, 6.28}) {
      const Vec3d w = sphericalDirection(theta, phi);
      EXPECT_NEAR(length(w), 1.0, 1e-15);
      EXPECT_NEAR(polarAngle(w), theta, 1e-12);
      EXPECT_NEAR(azimuth(w), phi, 1e-9);
      EXPECT_GE(azimuth(w), 0.0);
      EXPECT_LT(azimuth(w), 2.0 * std::numbers::pi);
    }
}

TEST(Sphere, ReflectIsAnInvolutionAboutTheNormal) {
  const Vec3d n = normalize({0.2, -0.3, 0.9});
  const Vec3d wo = normalize({-0.5, 0.1, 0.4});
  const Vec3d wi = reflect(wo, n);
  EXPECT_NEAR(length(wi), 1.0, 1e-15);
  EXPECT_NEAR(dot(wi, n), dot(wo, n), 1e-15);
  const Vec3d back = reflect(wi, n);
  EXPECT_NEAR(back.x, wo.x, 1e-15);
  EXPECT_NEAR(back.y, wo.y, 1e-15);
  EXPECT_NEAR(back.z, wo.z, 1e-15);
  const Vec3d h = normalize(wi + wo);
  EXPECT_NEAR(dot(h, n), 1.0, 1e-14);
}

TEST(Sphere, CosineHemisphereStaysAboveTheHorizonAtTheExtremeVariates) {
  for (float u0 : {0.0f, kOneMinusEpsilon})
    for (float u1 : {0.0f, kOneMinusEpsilon}) {
      const Vec3d w = sampleCosineHemisphere(u0, u1);
      EXPECT_GT(w.z, 0.0);
      EXPECT_GT(cosineHemispherePdf(w.z), 0.0);
    }
  EXPECT_GT(sampleCosineHemisphere(1.0, 0.5).z, 0.0);  // even u0 = 1 in double
}

ACDF_CHI_SQUARE_TEST(SphereChiSquare, UniformSpherePasses, 1) {
  const SphereChiSquareReport r = sphereChiSquareTest(uniformSphere, uniformSpherePdf, options());
  EXPECT_TRUE(r.passed()) << r.summary();
  EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-12) << "exact for a constant pdf";
}

ACDF_CHI_SQUARE_TEST(SphereChiSquare, CosineHemispherePasses, 1) {
  SphereChiSquareOptions o = options();
  o.subPoints = 16;
  const SphereChiSquareReport r = sphereChiSquareTest(cosineHemisphere, cosinePdf, o);
  EXPECT_TRUE(r.passed()) << r.summary();
  EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-5);
}

// Only the statistic is compared, no verdict: not in the family.
TEST(SphereChiSquare, ResultDoesNotDependOnThreadsOrRuns) {
  SphereChiSquareOptions o;
  o.samples = 300'000;
  const auto a = sphereChiSquareTest(cosineHemisphere, cosinePdf, o);
  const auto b = sphereChiSquareTest(cosineHemisphere, cosinePdf, o);
  EXPECT_EQ(a.chi2.statistic, b.chi2.statistic);
}

ACDF_CHI_SQUARE_TEST(SphereChiSquare, RejectsSamplesDrawnFromAnotherDistribution, 1) {
  const auto wrong = sphereChiSquareTest(
      [](float u0, float u1) {
        // Uniform on the upper hemisphere, reported with its true pdf, tested against cosθ/π.
        const Vec3d w = sampleUniformSphere(0.5f * u0, u1);
        return DirectionSample{w, cosineHemispherePdf(w.z)};
      },
      cosinePdf, options());
  EXPECT_FALSE(wrong.chiSquarePassed()) << wrong.summary();
}

ACDF_CHI_SQUARE_TEST(SphereChiSquare, RejectsASlightlyWrongPdf, 1) {
  // Cosine samples against a pdf 5% too high for θ < 30° and renormalised elsewhere.
  const double cos30 = std::cos(std::numbers::pi / 6);
  const double inside = 1.0 - cos30 * cos30;  // cosine mass within 30° of the pole
  const double scaleOutside = (1.0 - 1.05 * inside) / (1.0 - inside);
  auto skewed = [=](const Vec3d& w) { return cosineHemispherePdf(w.z) * (w.z > cos30 ? 1.05 : scaleOutside); };
  SphereChiSquareOptions o = options();
  o.subPoints = 16;
  const auto r = sphereChiSquareTest(
      [&](float u0, float u1) {
        const Vec3d w = sampleCosineHemisphere(u0, u1);
        return DirectionSample{w, skewed(w)};
      },
      skewed, o);
  EXPECT_TRUE(r.samplesValid()) << r.summary();
  EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-3);
  EXPECT_FALSE(r.chiSquarePassed()) << r.summary();
}

// The per-sample checks fail whatever the level: not in the family.
TEST(SphereChiSquare, CountsInconsistentPdfsAndInvalidSamples) {
  SphereChiSquareOptions o;
  o.samples = 10'000;
  const auto mismatched = sphereChiSquareTest(
      [](float u0, float u1) {
        return DirectionSample{sampleUniformSphere(u0, u1), 1.01 * kUniformSpherePdf};
      },
      uniformSpherePdf, o);
  EXPECT_EQ(mismatched.pdfMismatch, o.samples + 4) << "every sample and the four corners";
  EXPECT_FALSE(mismatched.passed());
  EXPECT_NE(mismatched.firstProblem.find("differs"), std::string::npos) << mismatched.firstProblem;

  const auto invalid = sphereChiSquareTest(
      [](float u0, float u1) {
        const Vec3d w = sampleUniformSphere(u0, u1);
        return DirectionSample{u0 == 0.0f ? Vec3d{0, 0, 0} : w, kUniformSpherePdf};
      },
      uniformSpherePdf, o);
  EXPECT_GE(invalid.invalidSamples, 2u) << "the corners with u0 = 0";
  EXPECT_FALSE(invalid.passed());

  const auto zeroPdf = sphereChiSquareTest(
      [](float u0, float u1) {
        return DirectionSample{sampleUniformSphere(u0, u1), 0.0};
      },
      uniformSpherePdf, o);
  EXPECT_EQ(zeroPdf.invalidSamples, o.samples + 4);
}

ACDF_CHI_SQUARE_TEST(SphereChiSquare, EqualAreaRowsAndCallerProbabilities, 2) {
  SphereChiSquareOptions o = options();
  o.equalAreaRows = true;
  o.thetaBins = 16;
  o.phiBins = 32;
  // Equal-area bins: the uniform sphere gives every bin the same probability, exactly.
  const std::vector<double> equal(std::size_t{16} * 32, 1.0 / (16 * 32));
  const auto r = sphereChiSquareTest(uniformSphere, uniformSpherePdf, equal, o);
  EXPECT_TRUE(r.passed()) << r.summary();
  EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-12);
  EXPECT_EQ(sphereBinOf({0, 0, 1}, o), 0u);
  EXPECT_EQ(sphereBinOf({0, 0, -1}, o), std::size_t{15} * 32);
  EXPECT_EQ(sphereBinOf(sphericalDirection(std::acos(1.0 - 2.0 * 1.5 / 16), 0.1), o), std::size_t{1} * 32);
  // The same samples against probabilities tilted towards the north pole are rejected.
  o.alpha = chiSquareTestLevel();
  std::vector<double> tilted(equal);
  for (std::size_t b = 0; b < tilted.size(); ++b) tilted[b] *= b < tilted.size() / 2 ? 1.02 : 0.98;
  EXPECT_FALSE(sphereChiSquareTest(uniformSphere, uniformSpherePdf, tilted, o).chiSquarePassed());
  EXPECT_THROW(sphereChiSquareTest(uniformSphere, uniformSpherePdf, std::vector<double>(3, 0.1), o),
               std::invalid_argument);
}

}  // namespace
