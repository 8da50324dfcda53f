#pragma once
// The family of chi-square tests of one test program, for the Šidák correction.
//
// Every chi-square test of a program runs at the level sidakAlpha(familyAlpha, m), m the number
// of chi-square tests the program registers, so the whole program fails a correct sampler with
// probability at most familyAlpha (1%). A test that runs chi-square tests says how many, in
// place of TEST / TEST_P:
//
//   ACDF_CHI_SQUARE_TEST(AliasGrid, SphericalDomain, 1) { ... }
//   ACDF_CHI_SQUARE_TEST_P(CascadeFixtures, ChiSquare, 1) { ... }  // 1 per instance
//
// m is counted in GoogleTest's list of the program's tests, disabled and filtered-out ones
// included: a TEST_P counts once per instance (parameters × instantiations), and a run under
// --gtest_filter, a shard or ctest's one process per test uses the level of the whole program.
//
// The count is checked. A chi-square run fails its test when the test is not registered, or has
// already run as many as it registered; a test that passes having run fewer fails the program
// (reported after the last test), and so does a registration that names no test.
//
// runChiSquare() (chi_square_harness.h) takes its level from chiSquareTestLevel(). A test calling
// another chi-square function (sphereChiSquareTest, lightChiSquareTest, brdfChiSquareTest) gives
// each call its own chiSquareTestLevel().

#include <gtest/gtest.h>

#include <cstdint>

namespace acdf::test_support {

// Records that every instance of the GoogleTest test `suite`.`name` runs `perTest` chi-square
// tests. Called by the macros below, at static initialisation; returns true.
bool registerChiSquareTests(const char* suite, const char* name, uint32_t perTest, const char* file, int line);

// m: the chi-square tests this program registers, over every instance of every registered test.
uint32_t chiSquareFamilySize();

// The level of one chi-square test, sidakAlpha(familyAlpha, chiSquareFamilySize()), counted as
// one run of the current test; adds a failure to it if that run is not registered.
double chiSquareTestLevel(double familyAlpha = 0.01);

}  // namespace acdf::test_support

#define ACDF_CHI_SQUARE_REGISTRATION_(suite, name, perTest)                           \
  [[maybe_unused]] static const bool acdf_chi_square_registered_##suite##_##name##_ = \
      ::acdf::test_support::registerChiSquareTests(#suite, #name, perTest, __FILE__, __LINE__)

// TEST(suite, name) that runs `perTest` chi-square tests.
#define ACDF_CHI_SQUARE_TEST(suite, name, perTest)     \
  ACDF_CHI_SQUARE_REGISTRATION_(suite, name, perTest); \
  TEST(suite, name)

// TEST_P(suite, name) each of whose instances runs `perTest` chi-square tests.
#define ACDF_CHI_SQUARE_TEST_P(suite, name, perTest)   \
  ACDF_CHI_SQUARE_REGISTRATION_(suite, name, perTest); \
  TEST_P(suite, name)
