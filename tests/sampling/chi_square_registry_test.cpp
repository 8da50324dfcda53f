// The chi-square registry (chi_square_registry.h): the family is every registered test instance of
// the program, whichever of them a filter runs, and each chi-square test runs at the Šidák level
// of that family; a run that is not registered fails its test. The failures reported after the
// last test (fewer runs than registered, a registration naming no test, a test registered twice)
// are checked by test_chi_square_registry_failures (chi_square_registry_failures.cpp).

#include "acdf/test_support/chi_square_registry.h"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <vector>

#include "acdf/sampling/chi_square.h"
#include "acdf/sampling/piecewise_constant_1d.h"
#include "acdf/test_support/chi_square_harness.h"

namespace {

using namespace acdf;
using namespace acdf::test_support;

// Registered below: Registry.OneRun 1, Registry.TwoRuns 2, RegistryParam.Runs 1 for each of
// 3 parameters × 2 instantiations, Registry.RunsBeyondTheRegistrationFail 1.
constexpr uint32_t kRegistered = 1 + 2 + 3 * 2 + 1;

// A cheap correct chi-square run: a uniform 1D table, 20k samples.
ChiSquareReport runUniform() {
  static const PiecewiseConstant1D table(std::vector<float>(16, 1.0f));
  const std::vector<GridAxis> axes = {table.axis()};
  ChiSquareOptions o;
  o.samples = 20'000;
  return runChiSquare(
      axes, [](float u) { return table.sample(u); }, [](float x) { return table.pdf(x); }, o);
}

TEST(Registry, FamilyIsEveryRegisteredInstance) { EXPECT_EQ(chiSquareFamilySize(), kRegistered); }

ACDF_CHI_SQUARE_TEST(Registry, OneRun, 1) {
  const ChiSquareReport r = runUniform();
  EXPECT_TRUE(Passed(r));
  EXPECT_EQ(r.alpha, sidakAlpha(0.01, kRegistered));
}

ACDF_CHI_SQUARE_TEST(Registry, TwoRuns, 2) {
  EXPECT_EQ(runUniform().alpha, sidakAlpha(0.01, kRegistered));
  EXPECT_EQ(chiSquareTestLevel(0.05), sidakAlpha(0.05, kRegistered)) << "another family level";
}

class RegistryParam : public ::testing::TestWithParam<int> {};

ACDF_CHI_SQUARE_TEST_P(RegistryParam, Runs, 1) { EXPECT_EQ(runUniform().alpha, sidakAlpha(0.01, kRegistered)); }

INSTANTIATE_TEST_SUITE_P(First, RegistryParam, ::testing::Values(1, 2, 3));
INSTANTIATE_TEST_SUITE_P(Second, RegistryParam, ::testing::Values(4, 5, 6));

TEST(Registry, AnUnregisteredRunFails) {
  EXPECT_NONFATAL_FAILURE(runUniform(), "Registry.AnUnregisteredRunFails, which is not registered");
  EXPECT_NONFATAL_FAILURE(chiSquareTestLevel(), "Registry.AnUnregisteredRunFails, which is not registered");
}

ACDF_CHI_SQUARE_TEST(Registry, RunsBeyondTheRegistrationFail, 1) {
  EXPECT_TRUE(Passed(runUniform()));
  EXPECT_NONFATAL_FAILURE(runUniform(), "ran chi-square test 2 but registered 1");
}

}  // namespace
